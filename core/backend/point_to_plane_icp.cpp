#include "core/backend/point_to_plane_icp.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "core/geometry/se3.hpp"

namespace dammloam::backend {

namespace {

struct VoxelKeyHash {
  std::size_t operator()(const Eigen::Vector3i& v) const {
    return static_cast<std::size_t>(v.x()) * 73856093u ^ static_cast<std::size_t>(v.y()) *
           19349663u ^ static_cast<std::size_t>(v.z()) * 83492791u;
  }
};

Eigen::Vector3d PcaNormal(const PointKdTree& tree, const Eigen::Vector3d& p, int k) {
  const auto neighbours = tree.Knn(p, static_cast<std::size_t>(k));
  if (neighbours.size() < 3) return Eigen::Vector3d::Zero();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (auto i : neighbours) mean += tree.points()[i];
  mean /= static_cast<double>(neighbours.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (auto i : neighbours) {
    const Eigen::Vector3d d = tree.points()[i] - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  // Neighbours along one line (a single far ring) leave the normal anywhere around that line:
  // no normal rather than a random one, which in a corridor would pose as information along
  // its axis.
  constexpr double kMinPlanarSpread = 0.05;  // second / largest eigenvalue
  if (solver.eigenvalues()(1) < kMinPlanarSpread * solver.eigenvalues()(2)) {
    return Eigen::Vector3d::Zero();
  }
  return solver.eigenvectors().col(0);  // smallest eigenvalue first
}

// Cauchy weight of a residual for counting information: pairs that do not fit their plane
// (far corners cut by one ring look like planes facing anywhere) must not count.
double Fit(double r, double kernel) { return 1.0 / (1.0 + (r / kernel) * (r / kernel)); }

}  // namespace

Eigen::Matrix3d SupportedDirections(const Eigen::Matrix3d& support, double min_support) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(support);
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (solver.eigenvalues()(i) >= min_support) {
      P.noalias() += solver.eigenvectors().col(i) * solver.eigenvectors().col(i).transpose();
    }
  }
  return P;
}

std::vector<std::size_t> VoxelDownsampleIndices(const std::vector<Eigen::Vector3d>& points,
                                                double voxel_size) {
  std::vector<std::size_t> kept;
  if (voxel_size <= 0.0) {
    kept.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) kept[i] = i;
    return kept;
  }
  std::unordered_set<Eigen::Vector3i, VoxelKeyHash> occupied;
  occupied.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    const Eigen::Vector3i key = (points[i] / voxel_size).array().floor().cast<int>();
    if (occupied.insert(key).second) kept.push_back(i);
  }
  return kept;
}

std::vector<Eigen::Vector3d> VoxelDownsample(const std::vector<Eigen::Vector3d>& points,
                                             double voxel_size) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i : VoxelDownsampleIndices(points, voxel_size)) out.push_back(points[i]);
  return out;
}

IcpTarget::IcpTarget(std::vector<Eigen::Vector3d> points, int normal_neighbours)
    : tree_(std::move(points)), normals_(tree_.size(), Eigen::Vector3d::Zero()) {
  tbb::parallel_for(std::size_t{0}, tree_.size(), [&](std::size_t i) {
    normals_[i] = PcaNormal(tree_, tree_.points()[i], normal_neighbours);
  });
}

IcpResult AlignPointToPlane(const std::vector<Eigen::Vector3d>& source, const IcpTarget& target,
                            const Eigen::Isometry3d& initial_T_target_source,
                            const IcpConfig& config) {
  IcpResult result;
  result.T_target_source = initial_T_target_source;
  if (source.empty() || target.size() < 3) return result;
  const int iterations = std::max(1, config.max_iterations);
  for (int it = 0; it < iterations; ++it) {
    // Correspondence gate shrinks over the first half of the iterations, then stays fine.
    const double progress = std::min(1.0, 2.0 * it / iterations);
    const double gate = config.initial_max_correspondence +
                        progress * (config.final_max_correspondence -
                                    config.initial_max_correspondence);
    const double kernel = gate / 3.0;
    Matrix6d H = Matrix6d::Zero();
    Vector6d b = Vector6d::Zero();
    for (const Eigen::Vector3d& s : source) {
      const Eigen::Vector3d p = result.T_target_source * s;
      std::uint32_t index = 0;
      double squared = 0.0;
      if (!target.tree().Nearest(p, index, squared) || squared > gate * gate) continue;
      const Eigen::Vector3d& n = target.normals()[index];
      if (n.isZero()) continue;
      const double r = n.dot(p - target.tree().points()[index]);
      Vector6d J;
      J << n, p.cross(n);
      const double w = 1.0 / (1.0 + (r / kernel) * (r / kernel));
      H += w * J * J.transpose();
      b += w * J * r;
    }
    if (H.trace() <= 0.0) break;
    // Tiny damping keeps degenerate directions (corridors) from blowing up the step.
    Vector6d dx = -(H + 1e-6 * Matrix6d::Identity()).ldlt().solve(b);
    if (config.min_direction_support > 0.0) {
      // Solution remapping: no step along directions the pairs do not support.
      dx.head<3>() = SupportedDirections(H.topLeftCorner<3, 3>(), config.min_direction_support) *
                     dx.head<3>();
    }
    result.T_target_source = Normalized(ExpSE3(dx) * result.T_target_source);
    result.iterations = it + 1;
    if (progress >= 1.0 && dx.norm() < config.convergence_step) {
      result.converged = true;
      break;
    }
  }
  // Quality: overlap and residual after alignment.
  std::size_t inliers = 0;
  double sum_squared = 0.0;
  Eigen::Matrix3d normal_scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& s : source) {
    const Eigen::Vector3d p = result.T_target_source * s;
    std::uint32_t index = 0;
    double squared = 0.0;
    if (!target.tree().Nearest(p, index, squared) ||
        squared > config.inlier_distance * config.inlier_distance) {
      continue;
    }
    const Eigen::Vector3d& n = target.normals()[index];
    const double r = n.isZero() ? std::sqrt(squared) : n.dot(p - target.tree().points()[index]);
    normal_scatter += n * n.transpose();
    Vector6d J;
    J << n, p.cross(n);
    result.hessian.noalias() += Fit(r, config.information_kernel) * J * J.transpose();
    sum_squared += r * r;
    ++inliers;
  }
  result.inlier_ratio = static_cast<double>(inliers) / static_cast<double>(source.size());
  result.rmse = inliers > 0 ? std::sqrt(sum_squared / static_cast<double>(inliers)) : 0.0;
  if (inliers > 0) {
    result.translation_observability =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(normal_scatter / static_cast<double>(inliers))
            .eigenvalues()(0);
  }
  return result;
}

}  // namespace dammloam::backend
