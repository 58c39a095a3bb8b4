#include "services/dds/ros2_messages.hpp"

#include <cstring>

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
  CloudMessage msg;
  msg.frame_id = frame_id;
  msg.width = static_cast<std::uint32_t>(points.points_sensor.size());
  const char* names[] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (std::uint32_t k = 0; k < 6; ++k) {
    msg.fields.push_back({names[k], 4 * k, dammloam_msg_DATATYPE_FLOAT32, 1});
  }
  msg.fields.push_back({"label", 24, dammloam_msg_DATATYPE_UINT8, 1});
  msg.point_step = 28;
  msg.row_step = msg.point_step * msg.width;
  msg.data.assign(std::size_t{msg.row_step}, 0);
  const bool has_normals = points.normals.size() == points.points_sensor.size();
  for (std::size_t i = 0; i < points.points_sensor.size(); ++i) {
    std::uint8_t* p = msg.data.data() + i * msg.point_step;
    const Eigen::Vector3f xyz = points.points_sensor[i].cast<float>();
    const Eigen::Vector3f normal = has_normals ? points.normals[i] : Eigen::Vector3f::Zero();
    const float values[6] = {xyz.x(), xyz.y(), xyz.z(), normal.x(), normal.y(), normal.z()};
    std::memcpy(p, values, sizeof(values));
    p[24] = static_cast<std::uint8_t>(points.labels[i]);
  }
  return msg;
}

Matrix6d PoseCovarianceToRos(const Matrix6d& covariance, const Eigen::Isometry3d& T_world_sensor) {
  Matrix6d J = Matrix6d::Identity();
  J.topRightCorner<3, 3>() = -Hat(T_world_sensor.translation());
  return J * covariance * J.transpose();
}

Matrix6d TwistCovarianceToRos(const Matrix6d& motion_covariance,
                              const Eigen::Isometry3d& T_world_sensor, double dt) {
  const Eigen::Matrix3d Rt = T_world_sensor.linear().transpose();
  Matrix6d ad_inverse = Matrix6d::Zero();  // Ad(T^-1) for the [rho; phi] order
  ad_inverse.topLeftCorner<3, 3>() = Rt;
  ad_inverse.topRightCorner<3, 3>() = -Rt * Hat(T_world_sensor.translation());
  ad_inverse.bottomRightCorner<3, 3>() = Rt;
  return ad_inverse * motion_covariance * ad_inverse.transpose() / (dt * dt);
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
