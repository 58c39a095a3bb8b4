#pragma once
// Conversions between core types and the small IDL message parts (poses, odometry).
#include <Eigen/Geometry>
#include <string>

#include "core/odometry/odometry_result.hpp"
#include "dammloam.h"

namespace dammloam::dds {

dammloam_msg_Pose3D ToMsgPose(const Eigen::Isometry3d& T);
Eigen::Isometry3d FromMsgPose(const dammloam_msg_Pose3D& pose);

// Fills everything the result knows. String members point into the given strings, which must
// outlive the sample; stamp/seq/latency are the caller's.
dammloam_msg_Odometry ToMsgOdometry(const OdometryResult& result, const std::string& map_frame,
                                    const std::string& sensor_frame,
                                    const std::string& status_name);

}  // namespace dammloam::dds
