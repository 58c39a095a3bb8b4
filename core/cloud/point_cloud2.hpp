#pragma once
// sensor_msgs/PointCloud2 content -> Scan, whatever carried the cloud: a DDS sample (services/dds)
// or a recorded message (io/bag). One floor below both so the field-layout rules (which fields
// mean x, time, ring, in which units) exist once.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/scan.hpp"

namespace dammloam {

// sensor_msgs/PointField datatype codes (same numbers as the ROS message constants).
namespace point_field {
inline constexpr std::uint8_t kInt8 = 1;
inline constexpr std::uint8_t kUint8 = 2;
inline constexpr std::uint8_t kInt16 = 3;
inline constexpr std::uint8_t kUint16 = 4;
inline constexpr std::uint8_t kInt32 = 5;
inline constexpr std::uint8_t kUint32 = 6;
inline constexpr std::uint8_t kFloat32 = 7;
inline constexpr std::uint8_t kFloat64 = 8;
}  // namespace point_field

// Bytes of one value of a datatype; 0 for an unknown code.
std::size_t PointFieldSize(std::uint8_t datatype);
// "float32", ..., or "unknown datatype N".
std::string PointFieldTypeName(std::uint8_t datatype);
// One value at p (host byte order, unaligned) as double; 0 for an unknown code.
double ReadPointFieldValue(const std::uint8_t* p, std::uint8_t datatype);

// builtin_interfaces/Time.
struct CloudStamp {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};
// Seconds as the double nearest to the decimal "sec.nanosec" (correctly rounded, so a stamp
// gives the same double as its decimal text in a sequence's times.txt).
double StampSeconds(const CloudStamp& stamp);
// Seconds -> stamp, rounded to the nearest nanosecond.
CloudStamp SecondsToStamp(double seconds);

// One PointField. Points into the message it was taken from.
struct CloudFieldView {
  std::string_view name;  // empty when the sample's name was null
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
  std::uint32_t count = 0;
};

// The sensor_msgs/PointCloud2 content of a message, whatever carried it. Points into the
// message: valid while it lives.
struct CloudInput {
  CloudStamp stamp;
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

// What to do with per-point times. Native input keeps them when present; the ROS 2 input makes
// the choice explicit (ros2.deskew: auto requires them, off ignores them).
enum class PointTimes {
  kOptional,  // read when present, else the scan is registered without deskew
  kRequired,  // a cloud without a time field is rejected (code "missing_time")
  kIgnored,   // never read: every scan is registered without deskew
};

// What is accepted; anything else is rejected with a message naming the problem.
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

struct CloudProblem {
  std::string code;     // short machine-readable category (DaemonStatus.rejected_by_reason)
  std::string message;  // empty when there is no problem
};

// Structural checks that do not look at points (stamp, byte order, sizes, fields, x y z
// types, steps, payload size); an empty message when the cloud is well formed.
CloudProblem CheckCloudLayout(const CloudInput& cloud, const CloudLimits& limits);

const CloudFieldView* FindCloudField(const CloudInput& cloud, std::string_view name);
// "point 7 (row 0, column 7)"
std::string CloudPointName(std::uint64_t index, std::uint32_t width);

struct CloudConversion {
  std::optional<Scan> scan;        // set on success
  std::string error;               // set on failure: what is wrong, naming the field/point
  std::string code;                // set on failure: short category, e.g. "payload_size"
  std::size_t skipped_points = 0;  // no-return points (all zero, or non-finite in non-dense clouds)
  // scan->t_start minus the stamp: negative when the stamp ends the sweep (stamp_may_end_scan).
  double start_offset = 0.0;
};

// Validates header, fields (names, types, offsets, counts), steps, payload size, byte order and
// every point, then converts; t_start = sec + nanosec * 1e-9 (the daemon's stamp arithmetic). Points exactly at the origin are no-returns and are skipped;
// non-finite points are skipped in clouds with is_dense=false and are an error otherwise.
// Reads x y z (float32|float64, required), intensity (any type, optional), per-point time
// since header.stamp from the first of t, time, time_stamp, timestamp (float32|float64 seconds
// or int32|uint32 nanoseconds; other types are an error), ring or channel (any type, optional).
// That covers ouster-ros (t uint32 ns, ring), velodyne_pointcloud (time float32 s, ring) and
// nebula (time_stamp uint32 ns, channel).
CloudConversion CloudToScan(const CloudInput& cloud, const CloudLimits& limits);

}  // namespace dammloam
