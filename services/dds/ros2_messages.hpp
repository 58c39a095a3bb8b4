#pragma once
// ROS 2 on the wire without ROS: topic names, QoS and conversions between core types and the
// ROS 2 message layouts of idl/ros2 (sensor_msgs PointCloud2, nav_msgs Odometry, tf2_msgs
// TFMessage). A ROS 2 topic /name is the DDS topic rt/name; its type is <pkg>::msg::dds_::<T>_.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/odometry/odometry_result.hpp"
#include "core/odometry/ros_covariance.hpp"
#include "nav_msgs.h"
#include "sensor_msgs.h"
#include "services/dds/dds.hpp"
#include "services/dds/point_cloud.hpp"
#include "tf2_msgs.h"

namespace dammloam::dds {

// "/points" and "points" -> "rt/points" (rmw's prefix for topics; relative names resolve in the
// root namespace, since dammloamd has no ROS node namespace).
std::string Ros2TopicName(const std::string& ros_name);
// The DDS topic of ROS 2's /tf.
inline constexpr const char* kRos2TfTopic = "rt/tf";

// rclcpp's QoS profiles, so ROS 2 endpoints match (a best-effort reader matches any writer; a
// reliable writer serves reliable and best-effort readers).
// SensorDataQoS: what LiDAR drivers publish with; keep-last 5, volatile.
inline TopicQos Ros2SensorDataQos() { return {false, 5, false}; }
// The default profile (rclcpp::QoS(10)): reliable, keep-last 10, volatile.
inline TopicQos Ros2OdometryQos() { return {true, 10, false}; }
inline TopicQos Ros2LabelledCloudQos() { return {true, 5, false}; }
// tf2_ros::TransformBroadcaster: reliable, keep-last 100, volatile.
inline TopicQos Ros2TfQos() { return {true, 100, false}; }

inline builtin_interfaces_msg_dds__Time_ ToRos2Time(const dammloam_msg_Time& t) {
  return {t.sec, t.nanosec};
}

// The vendor-neutral view of a ROS 2 cloud (validated and converted by CloudToScan).
CloudInput ViewOf(const sensor_msgs_msg_dds__PointCloud2_& cloud);

// The ROS 2 sample viewing a CloudMessage (its seq is dropped: ROS 2 headers have none); valid
// while both objects live and are not modified.
class Ros2CloudView {
 public:
  explicit Ros2CloudView(const CloudMessage& message);
  Ros2CloudView(const Ros2CloudView&) = delete;
  Ros2CloudView& operator=(const Ros2CloudView&) = delete;
  const sensor_msgs_msg_dds__PointCloud2_& get() const { return sample_; }

 private:
  std::vector<sensor_msgs_msg_dds__PointField_> fields_;
  sensor_msgs_msg_dds__PointCloud2_ sample_{};
};

// The labelled cloud for ROS 2 tools (RViz colours by label): the layout of
// core/cloud/labelled_cloud2.hpp (LabelledRos2Cloud), as a CloudMessage.
CloudMessage LabelledToRos2Cloud(const LabelledPoints& points, const std::string& frame_id);

// Covariance conventions (core/odometry/ros_covariance.hpp), shared with the MCAP output.
using ::dammloam::PoseCovarianceToRos;
using ::dammloam::TwistCovarianceToRos;

// nav_msgs/Odometry of one scan: pose = T_odom_sensor (the odometry, continuous), twist in the
// sensor frame. String members point into the given strings, which must outlive the sample.
nav_msgs_msg_dds__Odometry_ ToRos2Odometry(const OdometryResult& result,
                                           const dammloam_msg_Time& stamp,
                                           const std::string& odom_frame,
                                           const std::string& sensor_frame, double scan_period);

// One TF edge parent -> child (T_parent_child). Strings as above.
geometry_msgs_msg_dds__TransformStamped_ ToRos2Transform(const Eigen::Isometry3d& T_parent_child,
                                                         const dammloam_msg_Time& stamp,
                                                         const std::string& parent,
                                                         const std::string& child);

}  // namespace dammloam::dds
