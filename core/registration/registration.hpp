#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/se3.hpp"
#include "core/map/voxel_hash_map.hpp"
#include "core/odometry/odometry_result.hpp"
#include "core/registration/registration_config.hpp"

namespace dammloam {

struct RegistrationResult {
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Identity();  // [t; r], world-frame left perturbation
  DegeneracyReport degeneracy;
  double alpha = 0.0;
  std::uint32_t num_planar = 0;
  std::uint32_t num_point = 0;
  int iterations = 0;
  bool converged = false;
  bool enough_correspondences = false;  // false: the pose is the initial guess, untouched
};

// Robust Gauss-Newton on SE(3) of sensor-frame `source` points against the map, starting at
// `initial_guess` (paper Sec. III-B). Per iteration: class-wise correspondences within
// max_correspondence_distance, degeneracy weights on planar pairs, alpha between the planar
// and the point sums, Geman-McClure kernel of scale kernel_scale.
// prediction_is_motion_model: the guess extrapolates a motion model that has been holding, so
// full mode may keep it along degenerate directions (solution remapping); false after a
// start from rest or a reset, when every direction is left to the data.
RegistrationResult RegisterScan(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<PointClass>& labels, const VoxelHashMap& map,
                                const Eigen::Isometry3d& initial_guess,
                                double max_correspondence_distance, double kernel_scale,
                                const RegistrationConfig& config,
                                bool prediction_is_motion_model = true);

}  // namespace dammloam
