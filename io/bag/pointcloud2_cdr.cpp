#include "io/bag/pointcloud2_cdr.hpp"

#include <limits>

#include "io/bag/byte_cursor.hpp"
#include "io/bag/cdr_reader.hpp"

namespace dammloam::io {

DecodedCloud DecodePointCloud2(const std::uint8_t* data, std::size_t size,
                               std::uint64_t message_offset, const std::string& where) {
  CdrReader cdr(data, size, message_offset, where);
  DecodedCloud out;
  CloudInput& c = out.cloud;
  c.stamp.sec = cdr.I32("header.stamp.sec");
  c.stamp.nanosec = cdr.U32("header.stamp.nanosec");
  out.frame_id = std::string(cdr.String("header.frame_id"));
  c.height = cdr.U32("height");
  c.width = cdr.U32("width");
  // A PointField takes at least 4 (name length) + 4 + 1 + 4 bytes.
  const std::uint32_t num_fields = cdr.SequenceLength("fields", 13);
  out.field_names.reserve(num_fields);
  c.fields.reserve(num_fields);
  for (std::uint32_t i = 0; i < num_fields; ++i) {
    const std::string what = "fields[" + std::to_string(i) + "]";
    out.field_names.emplace_back(cdr.String(what + ".name"));
    CloudFieldView f;
    f.offset = cdr.U32(what + ".offset");
    f.datatype = cdr.U8(what + ".datatype");
    f.count = cdr.U32(what + ".count");
    c.fields.push_back(f);
  }
  c.is_bigendian = cdr.Bool("is_bigendian");
  c.point_step = cdr.U32("point_step");
  c.row_step = cdr.U32("row_step");
  const std::uint32_t data_size = cdr.SequenceLength("data", 1);
  c.data = cdr.Bytes(data_size, "data");
  c.data_size = data_size;
  c.is_dense = cdr.Bool("is_dense");
  // rmw pads a message to a multiple of 4 bytes; more than that is not a PointCloud2.
  if (cdr.remaining() >= 4) {
    cdr.Fail(std::to_string(cdr.remaining()) + " bytes after the end of the PointCloud2");
  }
  return out;
}

DecodedCloud DecodePointCloud2Ros1(const std::uint8_t* data, std::size_t size,
                                   std::uint64_t message_offset, const std::string& where) {
  ByteCursor in(data, size, message_offset, where);
  auto string = [&](const std::string& what) {
    const auto n = in.Read<std::uint32_t>(what + " length");
    const std::uint8_t* p = in.Bytes(n, what);
    return std::string(p, p + n);
  };
  DecodedCloud out;
  CloudInput& c = out.cloud;
  in.Read<std::uint32_t>("header.seq");
  const auto sec = in.Read<std::uint32_t>("header.stamp.sec");
  if (sec > static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::max())) {
    in.Fail("header.stamp.sec " + std::to_string(sec) + " is past 2038");
  }
  c.stamp.sec = static_cast<std::int32_t>(sec);
  c.stamp.nanosec = in.Read<std::uint32_t>("header.stamp.nsec");
  out.frame_id = string("header.frame_id");
  c.height = in.Read<std::uint32_t>("height");
  c.width = in.Read<std::uint32_t>("width");
  const auto num_fields = in.Read<std::uint32_t>("fields length");
  if (num_fields > in.remaining() / 13) {  // a PointField takes at least 4 + 4 + 1 + 4 bytes
    in.Fail(std::to_string(num_fields) + " fields do not fit in the message");
  }
  out.field_names.reserve(num_fields);
  c.fields.reserve(num_fields);
  for (std::uint32_t i = 0; i < num_fields; ++i) {
    const std::string what = "fields[" + std::to_string(i) + "]";
    out.field_names.push_back(string(what + ".name"));
    CloudFieldView f;
    f.offset = in.Read<std::uint32_t>(what + ".offset");
    f.datatype = in.Read<std::uint8_t>(what + ".datatype");
    f.count = in.Read<std::uint32_t>(what + ".count");
    c.fields.push_back(f);
  }
  c.is_bigendian = in.Read<std::uint8_t>("is_bigendian") != 0;
  c.point_step = in.Read<std::uint32_t>("point_step");
  c.row_step = in.Read<std::uint32_t>("row_step");
  const auto data_size = in.Read<std::uint32_t>("data length");
  c.data = in.Bytes(data_size, "data");
  c.data_size = data_size;
  c.is_dense = in.Read<std::uint8_t>("is_dense") != 0;
  if (in.remaining() != 0) {
    in.Fail(std::to_string(in.remaining()) + " bytes after the end of the PointCloud2");
  }
  return out;
}

CloudInput DecodedCloud::View() const {
  CloudInput view = cloud;
  for (std::size_t i = 0; i < view.fields.size(); ++i) view.fields[i].name = field_names[i];
  view.frame_id = frame_id;
  return view;
}

}  // namespace dammloam::io
