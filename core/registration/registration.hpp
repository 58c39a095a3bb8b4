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
#include "core/registration/registration_workspace.hpp"

namespace dammloam {

struct RegistrationResult {
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Identity();  // [t; r], world-frame left perturbation
  DegeneracyReport degeneracy;
  double alpha = 0.0;
  std::uint32_t num_planar = 0;
  std::uint32_t num_point = 0;
  int iterations = 0;
  int searches = 0;  // correspondence searches: iterations minus those that reused the pairs
  std::size_t searched_points = 0;  // source points looked up in the map, over all searches
  bool converged = false;
  bool enough_correspondences = false;  // false: the pose is the initial guess, untouched
  // Full mode: the scan's own information on the pose (without the prior), absolute units.
  Matrix6d data_information = Matrix6d::Zero();
  // Of that, the information on the position alone (rotation marginalised out: the Schur
  // complement), world frame, 1/m^2.
  Eigen::Matrix3d PositionInformation() const;
  // With in-scan motion (MotionPrior::scan_velocity_sigma): how the scan's own velocity
  // departs from the one it was deskewed with, sensor frame [v (m/s); w (rad/s)]. A point
  // fired at time tau (relative to the registered frame) belongs at ExpSE3(tau * scan_twist) p.
  Vector6d scan_twist = Vector6d::Zero();
  // With MotionPrior::scan_angular_acceleration_sigma as well: the scan's angular acceleration
  // (sensor frame, rad/s^2). The point fired at tau is then also turned about the sensor by
  // ExpSO3(0.5 (tau^2 - scan_mean_time_sq) scan_angular_acceleration); the mean of tau^2 over
  // the source points is taken off because a constant turn is the pose's.
  Eigen::Vector3d scan_angular_acceleration = Eigen::Vector3d::Zero();
  double scan_mean_time_sq = 0.0;  // s^2
};

// What the motion model predicts for a scan (the initial guess) and how far the carrier can
// depart from it within one scan period.
struct MotionPrior {
  // The model has held on recent scans (full_remap keeps the prediction along degenerate
  // directions only then).
  bool holds = true;
  // Full mode's prior factor: information on the sensor position (world frame, 1/m^2) and
  // 1-sigma departure of the orientation (rad) from the prediction. rotation_sigma 0: none.
  Eigen::Matrix3d translation_information = Eigen::Matrix3d::Zero();
  double rotation_sigma = 0.0;
  // Full mode's in-scan motion: 1-sigma departure of the scan's own linear (m/s) and angular
  // (rad/s) velocity from the velocity it was deskewed with. Both > 0 (and source times
  // given): that departure is estimated with the pose. 0: the deskew is taken as exact.
  double scan_velocity_sigma = 0.0;
  double scan_rate_sigma = 0.0;
  // With both above: 1-sigma angular acceleration (rad/s^2) within one scan, estimated too. A
  // hand's 4-9 Hz shake reverses its turn within a scan, which a constant rate cannot follow.
  double scan_angular_acceleration_sigma = 0.0;
  // Its own sigma about the sensor's spin axis (see InScanInformation); 0 holds it there, and
  // it is held there while a direction is weak.
  double scan_spin_axis_acceleration_sigma = 0.0;
  // Full mode with a gyroscope: its information on the orientation (world frame, 1/rad^2), which then
  // replaces rotation_sigma's isotropic one (rotation_sigma > 0 still selects the fused
  // solve). Zero: rotation_sigma's, as without an IMU.
  Eigen::Matrix3d rotation_information = Eigen::Matrix3d::Zero();
};

// Robust Gauss-Newton on SE(3) of sensor-frame `source` points against the map, starting at
// `initial_guess` (paper Sec. III-B). Per iteration: class-wise correspondences within
// max_correspondence_distance, degeneracy weights on planar pairs, alpha between the planar
// and the point sums, Geman-McClure kernel of scale kernel_scale.
// Full mode weighs the data's information (in absolute units, see residual_sigma) against the
// motion prior, direction by direction: along a direction the planes leave weak only pairs that
// really face it count, and the prior fills what they leave unobserved. full_remap is the
// paper's weighting plus solution remapping: it keeps the prediction along degenerate
// directions once prior.holds, and leaves every direction to the data otherwise.
// `source_times` (optional, one per source point): firing times relative to the frame the
// source is expressed in, seconds; with them and the prior's in-scan sigmas, full mode also
// estimates RegistrationResult::scan_twist. `workspace` (optional): the map's shapes kept
// from earlier scans, its owner having made workspace->shapes Forget the map's changes since
// (see ShapeCache), and buffers reused from scan to scan; without one, shapes are computed
// afresh and the buffers allocated for this scan.
RegistrationResult RegisterScan(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<PointClass>& labels, const VoxelHashMap& map,
                                const Eigen::Isometry3d& initial_guess,
                                double max_correspondence_distance, double kernel_scale,
                                const RegistrationConfig& config,
                                const MotionPrior& prior = {},
                                const std::vector<float>& source_times = {},
                                RegistrationWorkspace* workspace = nullptr);

}  // namespace dammloam
