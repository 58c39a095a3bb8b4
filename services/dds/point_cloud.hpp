#pragma once
// PointCloud (sensor_msgs/PointCloud2 layout) <-> Scan, with full validation of incoming clouds.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/scan.hpp"
#include "dammloam.h"

namespace dammloam::dds {

// Seconds <-> builtin_interfaces/Time (nanosecond resolution, rounded).
dammloam_msg_Time ToMsgTime(double seconds);
double ToSeconds(const dammloam_msg_Time& time);

struct CloudField {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = dammloam_msg_DATATYPE_FLOAT32;
  std::uint32_t count = 1;
};

// C++ owner of one PointCloud sample (the C type only points to memory it does not own).
struct CloudMessage {
  dammloam_msg_Time stamp{};
  std::string frame_id = "lidar";
  std::uint64_t seq = 0;
  std::uint32_t height = 1;
  std::uint32_t width = 0;
  std::vector<CloudField> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  std::vector<std::uint8_t> data;
  bool is_dense = true;
};

// The C sample viewing a CloudMessage; valid while both objects live and are not modified.
class CloudView {
 public:
  explicit CloudView(const CloudMessage& message);
  CloudView(const CloudView&) = delete;
  CloudView& operator=(const CloudView&) = delete;
  const dammloam_msg_PointCloud& get() const { return sample_; }

 private:
  std::vector<dammloam_msg_PointField> fields_;
  dammloam_msg_PointCloud sample_{};
};

// Fields x y z intensity (float32), t (float32 seconds since the stamp), ring (uint16);
// point_step 24, height 1, dense. Intensity/t/ring are written as 0 when the scan lacks them.
CloudMessage ScanToCloud(const Scan& scan, const std::string& frame_id, std::uint64_t seq);

// What to do with per-point times. Native input keeps them when present; the ROS 2 input makes
// the choice explicit (ros2.deskew: auto requires them, off ignores them).
enum class PointTimes {
  kOptional,  // read when present, else the scan is registered without deskew
  kRequired,  // a cloud without a time field is rejected (code "missing_time")
  kIgnored,   // never read: every scan is registered without deskew
};

// What the daemon accepts; anything else is rejected with a message naming the problem.
struct CloudLimits {
  std::uint64_t max_bytes = 32ull << 20;    // payload size limit (OS1-128 x 2048 is ~12 MiB)
  std::uint64_t max_points = 1u << 21;
  double max_point_time = 1.0;              // seconds after the stamp
  int max_ring = 1024;                      // exclusive; the daemon sets the sensor's rings
  PointTimes point_times = PointTimes::kOptional;
  // Per-point times may be negative, down to -max_point_time: the stamp is the end of the sweep
  // (velodyne_pointcloud stamps a cloud with its last packet). The scan is then re-referenced to
  // its first point: Scan::t_start = stamp + min(time), times shifted to start at 0.
  bool stamp_may_end_scan = false;
  // Appended to the "missing_time" error: which setting accepts such clouds.
  std::string missing_time_hint;
};

// One PointField, whatever IDL type carried it. Points into the sample it was taken from.
struct CloudFieldView {
  std::string_view name;  // empty when the sample's name was null
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
  std::uint32_t count = 0;
};

// The sensor_msgs/PointCloud2 content of an incoming sample, vendor-neutral: the native
// dammloam PointCloud and the ROS 2 PointCloud2_ both reduce to this (ViewOf below and in
// ros2_messages.hpp), so both inputs are validated and converted by the same code. Points into
// the sample: valid while it lives.
struct CloudInput {
  dammloam_msg_Time stamp{};
  std::string_view frame_id;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::vector<CloudFieldView> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  const std::uint8_t* data = nullptr;
  std::size_t data_size = 0;
  bool is_dense = true;
};

CloudInput ViewOf(const dammloam_msg_PointCloud& cloud);

// The native PointCloud and ROS 2's PointCloud2_ (both idlc-generated C) differ only in their
// header; these fill everything else, for either type, so the two adapters keep only the header.
template <typename CCloud>
CloudInput ViewOfBody(const CCloud& cloud) {
  CloudInput view;
  view.height = cloud.height;
  view.width = cloud.width;
  view.fields.reserve(cloud.fields._length);
  for (std::uint32_t i = 0; i < cloud.fields._length; ++i) {
    const auto& f = cloud.fields._buffer[i];
    view.fields.push_back({f.name != nullptr ? f.name : "", f.offset, f.datatype, f.count});
  }
  view.is_bigendian = cloud.is_bigendian;
  view.point_step = cloud.point_step;
  view.row_step = cloud.row_step;
  view.data = cloud.data._buffer;
  view.data_size = cloud.data._length;
  view.is_dense = cloud.is_dense;
  return view;
}

// Points `sample` (all but its header) at `message` and `fields`, which must outlive it.
template <typename CCloud, typename CField>
void ViewBodyOf(const CloudMessage& message, std::vector<CField>& fields, CCloud& sample) {
  fields.reserve(message.fields.size());
  for (const auto& f : message.fields) {
    fields.push_back({const_cast<char*>(f.name.c_str()), f.offset, f.datatype, f.count});
  }
  sample.height = message.height;
  sample.width = message.width;
  sample.fields._buffer = fields.data();
  sample.fields._length = sample.fields._maximum = static_cast<std::uint32_t>(fields.size());
  sample.fields._release = false;
  sample.is_bigendian = message.is_bigendian;
  sample.point_step = message.point_step;
  sample.row_step = message.row_step;
  sample.data._buffer = const_cast<std::uint8_t*>(message.data.data());
  sample.data._length = sample.data._maximum = static_cast<std::uint32_t>(message.data.size());
  sample.data._release = false;
  sample.is_dense = message.is_dense;
}

struct CloudConversion {
  std::optional<Scan> scan;        // set on success
  std::string error;               // set on failure: what is wrong, naming the field/point
  std::string code;                // set on failure: short category, e.g. "payload_size"
  std::size_t skipped_points = 0;  // no-return points (all zero, or non-finite in non-dense clouds)
  // scan->t_start minus the stamp: negative when the stamp ends the sweep (stamp_may_end_scan).
  double start_offset = 0.0;
};

// Validates header, fields (names, types, offsets, counts), steps, payload size, byte order and
// every point, then converts. Points exactly at the origin are no-returns and are skipped;
// non-finite points are skipped in clouds with is_dense=false and are an error otherwise.
// Reads x y z (float32|float64, required), intensity (any type, optional), per-point time
// since header.stamp from the first of t, time, time_stamp (float32|float64 seconds or
// int32|uint32 nanoseconds; other types are an error), ring or channel (any type, optional).
// That covers ouster-ros (t uint32 ns, ring), velodyne_pointcloud (time float32 s, ring) and
// nebula (time_stamp uint32 ns, channel).
CloudConversion CloudToScan(const CloudInput& cloud, const CloudLimits& limits);
CloudConversion CloudToScan(const dammloam_msg_PointCloud& cloud, const CloudLimits& limits);

// Labelled output cloud: x y z (sensor), map_x map_y map_z (map), normal_x normal_y normal_z
// (sensor), all float32, then label (uint8); point_step 40.
struct LabelledPoints {
  std::vector<Eigen::Vector3d> points_sensor;
  std::vector<Eigen::Vector3d> points_map;
  std::vector<Eigen::Vector3f> normals;  // may be empty
  std::vector<PointClass> labels;
};
CloudMessage LabelledToCloud(const LabelledPoints& points, const std::string& frame_id,
                             std::uint64_t seq);
// Inverse of LabelledToCloud for recorders and tests; error text on malformed input.
std::optional<LabelledPoints> CloudToLabelled(const dammloam_msg_PointCloud& cloud,
                                              std::string* error);

}  // namespace dammloam::dds
