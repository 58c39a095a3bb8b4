#pragma once
// Complete ros2msg definitions (the top-level .msg, then each dependency after a line of 80 '='
// and "MSG: pkg/Type") of the messages dammloam writes into MCAP, so that readers that
// know no ROS types (Foxglove, Lichtblick) can decode them. Field order is the CDR order of
// ros2_output.cpp; the definitions are those of ROS 2 Humble and later.
#include <string>

namespace dammloam::io {

const std::string& OdometrySchema();     // nav_msgs/msg/Odometry
const std::string& TfMessageSchema();    // tf2_msgs/msg/TFMessage
const std::string& PointCloud2Schema();  // sensor_msgs/msg/PointCloud2
const std::string& MarkerArraySchema();  // visualization_msgs/msg/MarkerArray
const std::string& StringSchema();       // std_msgs/msg/String

}  // namespace dammloam::io
