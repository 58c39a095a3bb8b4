#pragma once
// The labelled cloud as ROS 2 tools get it (dammloamd --ros2 and dammloam-odometry --mcap):
// one layout, packed here for both.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cloud/point_cloud2.hpp"
#include "core/geometry/point_class.hpp"

namespace dammloam {

struct Cloud2Field {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = point_field::kFloat32;
  std::uint32_t count = 1;
};

// A sensor_msgs/PointCloud2 that owns its bytes.
struct Cloud2 {
  CloudStamp stamp;
  std::string frame_id;
  std::uint32_t height = 1;
  std::uint32_t width = 0;
  std::vector<Cloud2Field> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  std::vector<std::uint8_t> data;
  bool is_dense = true;
};

// x y z normal_x normal_y normal_z (float32, sensor frame at the scan's start, deskewed) and
// label (uint8, the dammloam point class); point_step 28, height 1, dense. Normals are written
// as 0 when `normals` does not match the points. Map coordinates are left to TF.
Cloud2 LabelledRos2Cloud(const std::vector<Eigen::Vector3d>& points_sensor,
                         const std::vector<Eigen::Vector3f>& normals,
                         const std::vector<PointClass>& labels, const std::string& frame_id);

}  // namespace dammloam
