#include "tools/odometry/mcap_output.hpp"

#include "core/odometry/ros_covariance.hpp"
#include "io/bag/ros2_output.hpp"
#include "io/bag/ros2_schemas.hpp"

namespace dammloam::tools {
namespace {

std::uint64_t Nanoseconds(const CloudStamp& s) {
  return static_cast<std::uint64_t>(s.sec) * 1000000000ull + s.nanosec;
}

// rosbag2 needs the QoS a topic was offered with; empty means rclcpp's defaults.
const std::map<std::string, std::string> kChannelMetadata = {{"offered_qos_profiles", ""}};

}  // namespace

McapOutput::McapOutput(const std::filesystem::path& file, double scan_period,
                       const std::string& compression)
    : writer_(file, io::McapWriteOptions{compression}), scan_period_(scan_period) {
  const auto channel = [&](const char* type, const std::string& schema, const char* topic) {
    return writer_.AddChannel(writer_.AddSchema(type, "ros2msg", schema), topic, "cdr",
                              kChannelMetadata);
  };
  odometry_ = channel("nav_msgs/msg/Odometry", io::OdometrySchema(), "/dammloam/odometry");
  tf_ = channel("tf2_msgs/msg/TFMessage", io::TfMessageSchema(), "/tf");
  cloud_ = channel("sensor_msgs/msg/PointCloud2", io::PointCloud2Schema(),
                   "/dammloam/labelled_cloud");
  loops_ = channel("visualization_msgs/msg/MarkerArray", io::MarkerArraySchema(),
                   "/dammloam/loop_closures");
}

void McapOutput::AddScan(const OdometryResult& r, const Eigen::Isometry3d& T_map_odom) {
  const CloudStamp stamp = SecondsToStamp(r.stamp);
  const std::uint64_t t = Nanoseconds(stamp);
  const Eigen::Isometry3d& T = r.T_world_sensor;
  writer_.Write(odometry_, t, t,
                io::OdometryCdr(stamp, kOdomFrame, kSensorFrame, T,
                                PoseCovarianceToRos(r.pose_covariance, T), r.velocity,
                                TwistCovarianceToRos(r.covariance, T, scan_period_)));
  writer_.Write(tf_, t, t, io::TfCdr(stamp, kOdomFrame, kSensorFrame, T));
  writer_.Write(tf_, t, t, io::TfCdr(stamp, kMapFrame, kOdomFrame, T_map_odom));
  if (!r.deskewed_points.empty() && r.labels.size() == r.deskewed_points.size()) {
    Cloud2 cloud = LabelledRos2Cloud(r.deskewed_points, r.normals, r.labels, kSensorFrame);
    cloud.stamp = stamp;
    writer_.Write(cloud_, t, t, io::PointCloud2Cdr(cloud));
  }
  positions_[r.stamp] = T.translation();
}

void McapOutput::AddLoops(const std::vector<backend::LoopEvent>& events) {
  for (const backend::LoopEvent& e : events) {
    const auto query = positions_.find(e.query_stamp);
    const auto candidate = positions_.find(e.candidate_stamp);
    if (!e.accepted || query == positions_.end() || candidate == positions_.end()) continue;
    io::LineMarker marker;
    marker.ns = "loop_closures";
    marker.id = loop_count_++;
    marker.lines.emplace_back(candidate->second, query->second);
    const CloudStamp stamp = SecondsToStamp(e.query_stamp);
    writer_.Write(loops_, Nanoseconds(stamp), Nanoseconds(stamp),
                  io::LineMarkerArrayCdr(stamp, kOdomFrame, marker));
  }
}

}  // namespace dammloam::tools
