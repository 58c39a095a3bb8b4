#pragma once
#include <Eigen/Geometry>
#include <filesystem>
#include <vector>

namespace dammloam::io {

// A pose with its timestamp (seconds). T maps points of the body frame into the world frame.
struct StampedPose {
  double t = 0.0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
};

// TUM trajectory lines "t tx ty tz qx qy qz qw". Blank lines and '#' comments are skipped;
// quaternions are normalised. Errors name the file, the line number and the problem.
std::vector<StampedPose> ReadTum(const std::filesystem::path& file);

// Writes every value with full double precision (exact round trip through ReadTum up to the
// rotation -> quaternion conversion).
void WriteTum(const std::filesystem::path& file, const std::vector<StampedPose>& poses);

}  // namespace dammloam::io
