#pragma once
// PointCloud (sensor_msgs/PointCloud2 layout) <-> Scan, with full validation of incoming clouds.
#include <cstdint>
#include <optional>
#include <string>
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

// What the daemon accepts; anything else is rejected with a message naming the problem.
struct CloudLimits {
  std::uint64_t max_bytes = 32ull << 20;    // payload size limit (OS1-128 x 2048 is ~12 MiB)
  std::uint64_t max_points = 1u << 21;
  double max_point_time = 1.0;              // seconds after the stamp
  int max_ring = 1024;                      // exclusive; the daemon sets the sensor's rings
};

struct CloudConversion {
  std::optional<Scan> scan;        // set on success
  std::string error;               // set on failure: what is wrong, naming the field/point
  std::string code;                // set on failure: short category, e.g. "payload_size"
  std::size_t skipped_points = 0;  // no-return points (all zero, or non-finite in non-dense clouds)
};

// Validates header, fields (names, types, offsets, counts), steps, payload size, byte order and
// every point, then converts. Points exactly at the origin are no-returns and are skipped;
// non-finite points are skipped in clouds with is_dense=false and are an error otherwise.
// Reads x y z (float32|float64, required), intensity (optional), t (float32|float64 seconds or
// uint32 nanoseconds) or time (float32 seconds) (optional), ring (any integer or float type,
// optional).
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
