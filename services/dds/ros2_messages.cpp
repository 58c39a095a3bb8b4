#include "services/dds/ros2_messages.hpp"

#include <cstring>

#include "core/cloud/labelled_cloud2.hpp"
#include "services/dds/messages.hpp"

namespace dammloam::dds {
namespace {

geometry_msgs_msg_dds__Pose_ ToRos2Pose(const Eigen::Isometry3d& T) {
  const dammloam_msg_Pose3D p = ToMsgPose(T);
  return {{p.position.x, p.position.y, p.position.z},
          {p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w}};
}

void CopyRowMajor(const Matrix6d& m, double (&out)[36]) {
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) out[6 * r + c] = m(r, c);
  }
}

}  // namespace

std::string Ros2TopicName(const std::string& ros_name) {
  return ros_name.rfind('/', 0) == 0 ? "rt" + ros_name : "rt/" + ros_name;
}

CloudInput ViewOf(const sensor_msgs_msg_dds__PointCloud2_& cloud) {
  CloudInput view = ViewOfBody(cloud);
  view.stamp = {cloud.header.stamp.sec, cloud.header.stamp.nanosec};
  view.frame_id = cloud.header.frame_id != nullptr ? cloud.header.frame_id : "";
  return view;
}

Ros2CloudView::Ros2CloudView(const CloudMessage& message) {
  ViewBodyOf(message, fields_, sample_);
  sample_.header.stamp = ToRos2Time(message.stamp);
  sample_.header.frame_id = const_cast<char*>(message.frame_id.c_str());
}

CloudMessage LabelledToRos2Cloud(const LabelledPoints& points, const std::string& frame_id) {
  Cloud2 cloud = LabelledRos2Cloud(points.points_sensor, points.normals, points.labels, frame_id);
  CloudMessage msg;
  msg.frame_id = std::move(cloud.frame_id);
  msg.height = cloud.height;
  msg.width = cloud.width;
  for (const Cloud2Field& f : cloud.fields) msg.fields.push_back({f.name, f.offset, f.datatype, f.count});
  msg.is_bigendian = cloud.is_bigendian;
  msg.point_step = cloud.point_step;
  msg.row_step = cloud.row_step;
  msg.data = std::move(cloud.data);
  msg.is_dense = cloud.is_dense;
  return msg;
}

nav_msgs_msg_dds__Odometry_ ToRos2Odometry(const OdometryResult& result,
                                           const dammloam_msg_Time& stamp,
                                           const std::string& odom_frame,
                                           const std::string& sensor_frame, double scan_period) {
  nav_msgs_msg_dds__Odometry_ msg{};
  msg.header.stamp = ToRos2Time(stamp);
  msg.header.frame_id = const_cast<char*>(odom_frame.c_str());
  msg.child_frame_id = const_cast<char*>(sensor_frame.c_str());
  msg.pose.pose = ToRos2Pose(result.T_world_sensor);
  CopyRowMajor(PoseCovarianceToRos(result.pose_covariance, result.T_world_sensor),
               msg.pose.covariance);
  const Vector6d& v = result.velocity;
  msg.twist.twist = {{v(0), v(1), v(2)}, {v(3), v(4), v(5)}};
  CopyRowMajor(TwistCovarianceToRos(result.covariance, result.T_world_sensor, scan_period),
               msg.twist.covariance);
  return msg;
}

geometry_msgs_msg_dds__TransformStamped_ ToRos2Transform(const Eigen::Isometry3d& T_parent_child,
                                                         const dammloam_msg_Time& stamp,
                                                         const std::string& parent,
                                                         const std::string& child) {
  const geometry_msgs_msg_dds__Pose_ pose = ToRos2Pose(T_parent_child);
  geometry_msgs_msg_dds__TransformStamped_ msg{};
  msg.header.stamp = ToRos2Time(stamp);
  msg.header.frame_id = const_cast<char*>(parent.c_str());
  msg.child_frame_id = const_cast<char*>(child.c_str());
  msg.transform.translation = {pose.position.x, pose.position.y, pose.position.z};
  msg.transform.rotation = pose.orientation;
  return msg;
}

}  // namespace dammloam::dds
