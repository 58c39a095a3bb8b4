#include "io/bag/imu_messages.hpp"

#include <cmath>

#include "io/bag/bag_reader.hpp"
#include "io/bag/byte_cursor.hpp"
#include "io/bag/cdr_reader.hpp"
#include "io/bag/ros1_bag.hpp"

namespace dammloam::io {
namespace {

constexpr const char* kImuType = "sensor_msgs/msg/Imu";

// orientation (4), its covariance (9), angular velocity (3) and its covariance (9), linear
// acceleration (3) and its covariance (9): the body after the header, the same in both encodings
// but for CDR's alignment of the first double.
template <typename ReadF64>
ImuSample ImuBody(double stamp, ReadF64&& f64) {
  ImuSample s;
  s.t = stamp;
  for (int k = 0; k < 13; ++k) f64("orientation");
  for (int k = 0; k < 3; ++k) s.angular_velocity[k] = f64("angular_velocity");
  for (int k = 0; k < 9; ++k) f64("angular_velocity_covariance");
  for (int k = 0; k < 3; ++k) s.linear_acceleration[k] = f64("linear_acceleration");
  return s;
}

bool Finite(const ImuSample& s) {
  return std::isfinite(s.t) && s.angular_velocity.allFinite() && s.linear_acceleration.allFinite();
}

const BagTopic& PickImuTopic(const std::vector<BagTopic>& topics, const std::string& wanted,
                             const std::filesystem::path& bag, bool& found) {
  const BagTopic* pick = nullptr;
  std::size_t imu_topics = 0;
  for (const BagTopic& t : topics) {
    if (!wanted.empty() && t.name == wanted) pick = &t;
    if (wanted.empty() && t.type == kImuType) {
      ++imu_topics;
      pick = &t;
    }
  }
  if (!wanted.empty() && (pick == nullptr || pick->type != kImuType)) {
    throw IoError(bag.string() + ": no " + kImuType + " topic '" + wanted + "'; topics: " + TopicList(topics));
  }
  if (imu_topics > 1) {
    throw IoError(bag.string() + ": several " + kImuType + " topics, choose one with --imu-topic: " +
                  TopicList(topics));
  }
  found = pick != nullptr;
  return found ? *pick : topics.front();
}

}  // namespace

ImuSample DecodeImuCdr(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                       const std::string& where, std::string* frame_id) {
  CdrReader in(data, size, offset, where);
  const std::int32_t sec = in.I32("header.stamp.sec");
  const std::uint32_t nanosec = in.U32("header.stamp.nanosec");
  const std::string_view frame = in.String("header.frame_id");
  if (frame_id != nullptr) *frame_id = std::string(frame);
  return ImuBody(sec + 1e-9 * nanosec, [&](std::string_view what) { return in.F64(what); });
}

ImuSample DecodeImuRos1(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                        const std::string& where, std::string* frame_id) {
  ByteCursor in(data, size, offset, where);
  in.Read<std::uint32_t>("header.seq");
  const auto sec = in.Read<std::uint32_t>("header.stamp.sec");
  const auto nsec = in.Read<std::uint32_t>("header.stamp.nsec");
  const auto length = in.Read<std::uint32_t>("header.frame_id length");
  const std::uint8_t* frame = in.Bytes(length, "header.frame_id");
  if (frame_id != nullptr) frame_id->assign(frame, frame + length);
  return ImuBody(sec + 1e-9 * nsec, [&](std::string_view what) { return in.Read<double>(what); });
}

std::optional<BagImu> ReadBagImu(const std::filesystem::path& bag, const std::string& topic) {
  const std::unique_ptr<BagReader> reader = OpenBag(bag);
  if (reader->topics().empty()) return std::nullopt;
  bool found = false;
  const BagTopic& picked = PickImuTopic(reader->topics(), topic, bag, found);
  if (!found) return std::nullopt;
  BagImu out;
  out.topic = picked.name;
  const bool ros1 = picked.serialization_format == kRos1Serialization;
  reader->Select(picked.name);
  BagMessage m;
  int index = 0;
  const auto drop = [&](SampleFault fault, std::size_t& count) {
    ++count;
    if (out.report.first_dropped.size() < StreamReadReport::kMaxListed) {
      out.report.first_dropped.push_back({index, fault});
    }
  };
  while (reader->Next(m)) {
    ++index;
    std::string frame;
    const ImuSample s = ros1 ? DecodeImuRos1(m.data, m.size, m.data_offset, m.where, &frame)
                             : DecodeImuCdr(m.data, m.size, m.data_offset, m.where, &frame);
    if (out.frame_id.empty()) out.frame_id = frame;
    if (!Finite(s)) {
      drop(SampleFault::kNonFinite, out.report.non_finite);
    } else if (!out.samples.empty() && s.t == out.samples.back().t) {
      drop(SampleFault::kDuplicateStamp, out.report.duplicate_stamp);
    } else if (!out.samples.empty() && s.t < out.samples.back().t) {
      drop(SampleFault::kOutOfOrderStamp, out.report.out_of_order);
    } else {
      out.samples.push_back(s);
    }
  }
  out.report.kept = out.samples.size();
  return out;
}

}  // namespace dammloam::io
