#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/backend/point_kdtree.hpp"
#include "core/geometry/se3.hpp"

namespace dammloam::backend {

// Indices of one point per voxel (the first seen), so callers can keep labels aligned.
std::vector<std::size_t> VoxelDownsampleIndices(const std::vector<Eigen::Vector3d>& points,
                                                double voxel_size);
std::vector<Eigen::Vector3d> VoxelDownsample(const std::vector<Eigen::Vector3d>& points,
                                             double voxel_size);

// A fixed cloud to register against: points, PCA normals and a k-d tree, built once.
class IcpTarget {
 public:
  explicit IcpTarget(std::vector<Eigen::Vector3d> points, int normal_neighbours = 10);
  const PointKdTree& tree() const { return tree_; }
  const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
  std::size_t size() const { return tree_.size(); }

 private:
  PointKdTree tree_;
  std::vector<Eigen::Vector3d> normals_;
};

struct IcpConfig {
  int max_iterations = 40;
  double initial_max_correspondence = 3.0;  // metres; shrinks to the final value (coarse to fine)
  double final_max_correspondence = 0.6;
  double inlier_distance = 0.3;             // nearest-neighbour distance counted as overlap
  double convergence_step = 1e-4;           // stop when the update is this small (m / rad)
  // When > 0, translation steps are kept only along directions whose normals hold at least
  // this many (robust-weighted) points' worth of support: along a corridor's axis the few far
  // points that see its ends are outvoted by small biases of thousands of wall points, and an
  // unconstrained alignment slides towards "no motion" (solution remapping).
  double min_direction_support = 0.0;
  // Cauchy scale (metres) of the final residuals weighting the pairs in IcpResult::hessian.
  double information_kernel = 0.05;

  bool operator==(const IcpConfig&) const = default;
};

struct IcpResult {
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  double inlier_ratio = 0.0;  // share of source points within inlier_distance after alignment
  double rmse = 0.0;          // point-to-plane residual RMS over those inliers, metres
  // Smallest eigenvalue of sum(n n^T) / inliers over the inlier normals: near 0 when some
  // translation direction is unconstrained (a featureless corridor), at most 1/3.
  double translation_observability = 0.0;
  // Gauss-Newton information of the final alignment at unit noise: sum w J J^T over the inlier
  // point-to-plane pairs (w: Cauchy weight of the residual, scale information_kernel),
  // J = [n; p x n] for a left perturbation of T_target_source, tangent [t; r]. Divide by the
  // noise variance for a Fisher information; near singular along the directions the scene
  // leaves free.
  Matrix6d hessian = Matrix6d::Zero();
  int iterations = 0;
  bool converged = false;
};

// Projector onto the eigen-directions of a translational support scatter (sum of weighted
// n n^T) whose eigenvalue reaches min_support: the translation directions a registration fixes.
Eigen::Matrix3d SupportedDirections(const Eigen::Matrix3d& support, double min_support);

// Compact robust point-to-plane ICP (paper eq. pt2pl) used by loop verification and
// localization; Gauss-Newton on SE(3) with a Cauchy-type weight.
IcpResult AlignPointToPlane(const std::vector<Eigen::Vector3d>& source, const IcpTarget& target,
                            const Eigen::Isometry3d& initial_T_target_source,
                            const IcpConfig& config = {});

}  // namespace dammloam::backend
