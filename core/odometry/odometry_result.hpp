#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/se3.hpp"

namespace dammloam {

// Observability of translation: eigen-decomposition of the translational 3x3 block of the
// registration Hessian (paper eq. H_tt = V_t Sigma_t V_t^T), eigenvalues ascending.
struct DegeneracyReport {
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();
  Eigen::Matrix3d eigenvectors = Eigen::Matrix3d::Identity();  // columns, world frame
  std::array<bool, 3> degenerate{false, false, false};         // per eigen-direction
};

struct StageTimings {
  double projection_ms = 0, normals_ms = 0, classification_ms = 0, deskew_ms = 0,
         downsample_ms = 0, registration_ms = 0, map_update_ms = 0, total_ms = 0;
};

// Everything downstream users need about one registered scan.
struct OdometryResult {
  double stamp = 0.0;                                         // scan start time, seconds
  std::uint64_t scan_index = 0;
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();  // at scan start
  Matrix6d covariance = Matrix6d::Identity();                 // tangent order [t; r]
  Vector6d velocity = Vector6d::Zero();                       // [v; w] in sensor frame, per s
  DegeneracyReport degeneracy;
  double alpha = 0.0;                                         // planar share (GenZ-style)
  ClassCounts class_counts{};                                 // of the input scan
  std::uint32_t num_correspondences = 0;
  int iterations = 0;
  bool converged = false;
  StageTimings timings;
  // The deskewed scan in the sensor frame at scan start, with labels and normals, for
  // LabelledCloud publishing and keyframes.
  std::vector<Eigen::Vector3d> deskewed_points;
  std::vector<PointClass> labels;
  std::vector<Eigen::Vector3f> normals;
};

}  // namespace dammloam
