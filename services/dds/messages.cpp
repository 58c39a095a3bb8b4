#include "services/dds/messages.hpp"

namespace dammloam::dds {

dammloam_msg_Pose3D ToMsgPose(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d t = T.translation();
  return {{t.x(), t.y(), t.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

Eigen::Isometry3d FromMsgPose(const dammloam_msg_Pose3D& pose) {
  const auto& o = pose.orientation;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(o.w, o.x, o.y, o.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return T;
}

dammloam_msg_Odometry ToMsgOdometry(const OdometryResult& result, const std::string& map_frame,
                                    const std::string& sensor_frame,
                                    const std::string& status_name) {
  dammloam_msg_Odometry msg{};
  msg.header.frame_id = const_cast<char*>(map_frame.c_str());
  msg.child_frame_id = const_cast<char*>(sensor_frame.c_str());
  msg.status = const_cast<char*>(status_name.c_str());
  msg.registered = Registered(result.status);
  msg.scan_index = result.scan_index;
  msg.pose = ToMsgPose(result.T_world_sensor);
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) msg.covariance[6 * r + c] = result.pose_covariance(r, c);
  }
  msg.linear_velocity = {result.velocity(0), result.velocity(1), result.velocity(2)};
  msg.angular_velocity = {result.velocity(3), result.velocity(4), result.velocity(5)};
  for (int i = 0; i < 3; ++i) {
    msg.degeneracy.eigenvalues[i] = result.degeneracy.eigenvalues(i);
    msg.degeneracy.degenerate[i] = result.degeneracy.degenerate[static_cast<std::size_t>(i)];
    for (int j = 0; j < 3; ++j) {
      msg.degeneracy.eigenvectors[3 * i + j] = result.degeneracy.eigenvectors(i, j);
    }
  }
  msg.alpha = result.alpha;
  for (std::size_t k = 0; k < result.class_counts.size(); ++k) {
    msg.class_counts[k] = result.class_counts[k];
  }
  msg.num_correspondences = result.num_correspondences;
  msg.iterations = result.iterations;
  msg.converged = result.converged;
  msg.processing_ms = result.timings.total_ms;
  // Names are string_views into static storage: NUL-terminated literals.
  msg.tracking = const_cast<char*>(Name(result.tracking).data());
  msg.point_times = const_cast<char*>(Name(result.point_times).data());
  return msg;
}

}  // namespace dammloam::dds
