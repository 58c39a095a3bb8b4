#pragma once
// CDR bytes of the ROS 2 messages dammloam writes into MCAP (schemas in ros2_schemas.hpp).
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/cloud/labelled_cloud2.hpp"
#include "core/geometry/se3.hpp"

namespace dammloam::io {

// nav_msgs/msg/Odometry: pose T_parent_child with its covariance, twist in the child frame
// with its covariance (both 6x6 in ROS order, row-major on the wire).
std::vector<std::uint8_t> OdometryCdr(const CloudStamp& stamp, const std::string& parent,
                                      const std::string& child, const Eigen::Isometry3d& pose,
                                      const Matrix6d& pose_covariance, const Vector6d& twist,
                                      const Matrix6d& twist_covariance);

// tf2_msgs/msg/TFMessage with one transform parent -> child (T_parent_child).
std::vector<std::uint8_t> TfCdr(const CloudStamp& stamp, const std::string& parent,
                                const std::string& child, const Eigen::Isometry3d& T);

// std_msgs/msg/String.
std::vector<std::uint8_t> StringCdr(std::string_view text);

// sensor_msgs/msg/PointCloud2.
std::vector<std::uint8_t> PointCloud2Cdr(const Cloud2& cloud);

// visualization_msgs/msg/MarkerArray with one LINE_LIST marker (namespace ns, id): a line per
// pair of points, all in one colour (r g b a).
struct LineMarker {
  std::string ns;
  std::int32_t id = 0;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines;
  float rgba[4] = {0.f, 1.f, 0.f, 1.f};
  double width = 0.1;  // metres (scale.x)
};
std::vector<std::uint8_t> LineMarkerArrayCdr(const CloudStamp& stamp, const std::string& frame,
                                             const LineMarker& marker);

}  // namespace dammloam::io
