#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/se3.hpp"
#include "core/inertial/gyro_integration.hpp"
#include "core/inertial/velocity_increment.hpp"
#include "core/inertial/wheel_integration.hpp"
#include "core/odometry/tracking_health.hpp"
#include "core/preprocess/point_times.hpp"

namespace dammloam {

// Observability of translation: eigen-decomposition of the translational 3x3 block of the
// registration Hessian (paper eq. H_tt = V_t Sigma_t V_t^T), eigenvalues ascending.
struct DegeneracyReport {
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();
  Eigen::Matrix3d eigenvectors = Eigen::Matrix3d::Identity();  // columns, world frame
  std::array<bool, 3> degenerate{false, false, false};         // per eigen-direction
  bool AnyDegenerate() const { return degenerate[0] || degenerate[1] || degenerate[2]; }
};

// What happened to a scan. Only kOk, kFirstScan, kTimeGap and kRestarted registered it and
// updated the map; the others leave the odometry state untouched and report the last (or
// predicted) pose.
enum class OdometryStatus : std::uint8_t {
  kOk = 0,
  kFirstScan,              // initialised the map; pose is identity
  kTimeGap,                // registered, but the gap exceeded max_time_gap: velocity was reset
  kEmptyScan,              // no valid point
  kTooFewPoints,           // fewer valid points than OdometryConfig::min_points
  kNonIncreasingStamp,     // stamp <= previous stamp (duplicate or out of order)
  kTooFewCorrespondences,  // registration found too few pairs; pose is the prediction
  kLost,                   // registration fitted far worse than recent scans (TrackingHealth),
                           // also from a wider search; pose is the prediction
  kRestarted,              // after consecutive lost scans the local map was started over at
                           // the prediction with this scan
};

constexpr bool Registered(OdometryStatus s) {
  return s == OdometryStatus::kOk || s == OdometryStatus::kFirstScan ||
         s == OdometryStatus::kTimeGap || s == OdometryStatus::kRestarted;
}

constexpr std::string_view Name(OdometryStatus s) {
  switch (s) {
    case OdometryStatus::kOk: return "ok";
    case OdometryStatus::kFirstScan: return "first_scan";
    case OdometryStatus::kTimeGap: return "time_gap";
    case OdometryStatus::kEmptyScan: return "empty_scan";
    case OdometryStatus::kTooFewPoints: return "too_few_points";
    case OdometryStatus::kNonIncreasingStamp: return "non_increasing_stamp";
    case OdometryStatus::kTooFewCorrespondences: return "too_few_correspondences";
    case OdometryStatus::kLost: return "lost";
    case OdometryStatus::kRestarted: return "restarted";
  }
  return "unknown";
}

struct StageTimings {
  double projection_ms = 0, normals_ms = 0, classification_ms = 0, deskew_ms = 0,
         downsample_ms = 0, registration_ms = 0, map_update_ms = 0, total_ms = 0;
};

// Everything downstream users need about one registered scan.
struct OdometryResult {
  double stamp = 0.0;                                         // scan start time, seconds
  std::uint64_t scan_index = 0;
  OdometryStatus status = OdometryStatus::kOk;
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();  // at scan start
  // Of this scan's registration (the motion since the last scan), tangent order [t; r]: what
  // the pose graph's odometry edges sum.
  Matrix6d covariance = Matrix6d::Identity();
  // Of the pose in the odometry frame: the registration's, plus along the directions that have
  // been degenerate since they were last observed, everything accumulated while they were.
  Matrix6d pose_covariance = Matrix6d::Identity();
  Vector6d velocity = Vector6d::Zero();                       // [v; w] in sensor frame, per s
  DegeneracyReport degeneracy;
  double alpha = 0.0;                                         // planar share (GenZ-style)
  ClassCounts class_counts{};                                 // of the input scan
  std::uint32_t num_correspondences = 0;
  std::size_t map_points = 0;  // in the local map after this scan (cropped: stays bounded)
  int iterations = 0;
  // Source points looked up in the map over all correspondence searches: the search's work,
  // which unlike its time does not depend on the machine's load.
  std::size_t searched_points = 0;
  bool converged = false;
  // Whether the scan's point times drove its deskew (kUsable) or why not: a scan whose times
  // are absent, constant or out of firing order is registered as instantaneous.
  PointTimeCheck point_times = PointTimeCheck::kUsable;
  // Whether the pose is measured (TrackingHealth): tracking, degraded, or lost (not registered,
  // for any reason but a duplicate stamp; the pose is the prediction).
  Tracking tracking = Tracking::kTracking;
  double innovation = 0.0;  // metres: the registered pose against the constant-velocity prediction
  double turn_innovation_deg = 0.0;  // the same for the orientation
  double paired_share = 0.0;  // of the registration's source points that found a pair
  double correspondence_gate = 0.0;  // metres: 3 sigma of the adaptive threshold, this scan's
  StageTimings timings;
  // The deskewed scan in the sensor frame at scan start, with labels and normals, for
  // LabelledCloud publishing and keyframes.
  std::vector<Eigen::Vector3d> deskewed_points;
  std::vector<PointClass> labels;
  std::vector<Eigen::Vector3f> normals;
  // Per deskewed point, 1 where it lies on something that moves (config.moving.enabled; else
  // empty). Such points were left out of registration and of the map.
  std::vector<std::uint8_t> moving;
  std::size_t map_points_moved_away = 0;  // removed from the map by this scan
  // Points kept out of registration and map because they lie on compact objects that would
  // have been the main witnesses of the scan's weakest direction (CompactObjects).
  std::size_t set_aside_points = 0;
  // With an IMU (Odometry::EnableImu): whether its gyro covered this scan (kCovered: used) or
  // why the scan fell back to the LiDAR alone; empty without an IMU.
  std::optional<GyroCoverage> gyro;
  // With wheel odometry (Odometry::EnableWheel): whether it covered the interval from the
  // previous scan (kCovered: its motion was the prediction's translation and a prior), or why
  // the scan fell back to the LiDAR and the constant-velocity model; empty without it.
  std::optional<WheelCoverage> wheel;
  // With the accelerometer on (OdometryConfig::accelerometer): whether it covered the interval,
  // and whether its velocity change drove the motion prior (gravity learned, no wheels).
  std::optional<AccelCoverage> accelerometer;
  bool accelerometer_used = false;
};

}  // namespace dammloam
