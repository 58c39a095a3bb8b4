#pragma once
// PointCloud (sensor_msgs/PointCloud2 layout) <-> Scan, with full validation of incoming clouds.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/cloud/point_cloud2.hpp"
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

// The PointCloud2 content and its conversion live in core (core/cloud/point_cloud2.hpp), shared
// with the recorded-bag input of io/bag; these names keep the DDS code's spelling.
using ::dammloam::CloudConversion;
using ::dammloam::CloudFieldView;
using ::dammloam::CloudInput;
using ::dammloam::CloudLimits;
using ::dammloam::CloudToScan;
using ::dammloam::PointTimes;

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

// CloudToScan (core) on the native sample.
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
