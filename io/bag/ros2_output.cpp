#include "io/bag/ros2_output.hpp"

#include "io/bag/cdr_writer.hpp"

namespace dammloam::io {
namespace {

void Header(CdrWriter& w, const CloudStamp& stamp, const std::string& frame) {
  w.I32(stamp.sec);
  w.U32(stamp.nanosec);
  w.String(frame);
}

void Vector(CdrWriter& w, const Eigen::Vector3d& v) {
  w.F64(v.x());
  w.F64(v.y());
  w.F64(v.z());
}

void Rotation(CdrWriter& w, const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  w.F64(q.x());
  w.F64(q.y());
  w.F64(q.z());
  w.F64(q.w());
}

void Covariance(CdrWriter& w, const Matrix6d& m) {
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) w.F64(m(r, c));
  }
}

}  // namespace

std::vector<std::uint8_t> OdometryCdr(const CloudStamp& stamp, const std::string& parent,
                                      const std::string& child, const Eigen::Isometry3d& pose,
                                      const Matrix6d& pose_covariance, const Vector6d& twist,
                                      const Matrix6d& twist_covariance) {
  CdrWriter w;
  Header(w, stamp, parent);
  w.String(child);
  Vector(w, pose.translation());
  Rotation(w, pose.linear());
  Covariance(w, pose_covariance);
  Vector(w, twist.head<3>());
  Vector(w, twist.tail<3>());
  Covariance(w, twist_covariance);
  return w.Take();
}

std::vector<std::uint8_t> TfCdr(const CloudStamp& stamp, const std::string& parent,
                                const std::string& child, const Eigen::Isometry3d& T) {
  CdrWriter w;
  w.U32(1);
  Header(w, stamp, parent);
  w.String(child);
  Vector(w, T.translation());
  Rotation(w, T.linear());
  return w.Take();
}

std::vector<std::uint8_t> StringCdr(std::string_view text) {
  CdrWriter w;
  w.String(text);
  return w.Take();
}

std::vector<std::uint8_t> PointCloud2Cdr(const Cloud2& cloud) {
  CdrWriter w;
  Header(w, cloud.stamp, cloud.frame_id);
  w.U32(cloud.height);
  w.U32(cloud.width);
  w.U32(static_cast<std::uint32_t>(cloud.fields.size()));
  for (const Cloud2Field& f : cloud.fields) {
    w.String(f.name);
    w.U32(f.offset);
    w.U8(f.datatype);
    w.U32(f.count);
  }
  w.Bool(cloud.is_bigendian);
  w.U32(cloud.point_step);
  w.U32(cloud.row_step);
  w.Bytes(cloud.data);
  w.Bool(cloud.is_dense);
  return w.Take();
}

std::vector<std::uint8_t> LineMarkerArrayCdr(const CloudStamp& stamp, const std::string& frame,
                                             const LineMarker& marker) {
  constexpr std::int32_t kLineList = 5, kAdd = 0;
  CdrWriter w;
  w.U32(1);  // markers
  Header(w, stamp, frame);
  w.String(marker.ns);
  w.I32(marker.id);
  w.I32(kLineList);
  w.I32(kAdd);
  Vector(w, Eigen::Vector3d::Zero());  // pose: identity
  Rotation(w, Eigen::Matrix3d::Identity());
  Vector(w, Eigen::Vector3d(marker.width, 0.0, 0.0));  // scale.x = line width
  for (float c : marker.rgba) w.F32(c);
  w.I32(0);  // lifetime 0 = forever
  w.U32(0);
  w.Bool(false);  // frame_locked
  w.U32(static_cast<std::uint32_t>(2 * marker.lines.size()));
  for (const auto& [a, b] : marker.lines) {
    Vector(w, a);
    Vector(w, b);
  }
  w.U32(0);               // colors
  w.String("");           // texture_resource
  Header(w, stamp, "");   // texture.header
  w.String("");           // texture.format
  w.Bytes({});            // texture.data
  w.U32(0);               // uv_coordinates
  w.String("");           // text
  w.String("");           // mesh_resource
  w.String("");           // mesh_file.filename
  w.Bytes({});            // mesh_file.data
  w.Bool(false);          // mesh_use_embedded_materials
  return w.Take();
}

}  // namespace dammloam::io
