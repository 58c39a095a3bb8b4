#include "core/registration/registration.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/registration/correspondences.hpp"
#include "core/registration/degeneracy_weights.hpp"

namespace dammloam {

namespace {

// Normal equations of the weighted objective; tangent order [t; r] (see degeneracy_weights.hpp).
struct LinearSystem {
  Matrix6d H = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  double chi2 = 0.0;  // weighted squared residual sum
  LinearSystem& operator+=(const LinearSystem& o) {
    H += o.H;
    b += o.b;
    chi2 += o.chi2;
    return *this;
  }
};

// Geman-McClure IRLS weight, KISS-ICP's form.
double RobustWeight(double residual_sq, double kernel_scale) {
  const double d = kernel_scale + residual_sq;
  return kernel_scale * kernel_scale / (d * d);
}

// Fixed-size blocks and a deterministic reduction: the sum's rounding does not depend on
// thread scheduling, so identical inputs give bit-identical poses.
template <typename Fn>
LinearSystem ReduceDeterministic(std::size_t n, Fn add_term) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, 512), LinearSystem{},
      [&](const tbb::blocked_range<std::size_t>& r, LinearSystem acc) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) add_term(i, acc);
        return acc;
      },
      [](LinearSystem a, const LinearSystem& b) { return a += b; });
}

// Point-to-plane: r = n^T (s - q), J = [n^T, (s x n)^T] (paper eq. pt2pl).
LinearSystem PlanarSystem(const std::vector<Correspondence>& pairs,
                          const std::vector<double>& weights, double alpha, double kernel_scale) {
  return ReduceDeterministic(pairs.size(), [&](std::size_t i, LinearSystem& acc) {
    const Correspondence& c = pairs[i];
    const double r = c.normal.dot(c.source - c.target);
    Vector6d J;
    J << c.normal, c.source.cross(c.normal);
    const double w = alpha * weights[i] * RobustWeight(r * r, kernel_scale);
    acc.H.noalias() += w * J * J.transpose();
    acc.b.noalias() += w * r * J;
    acc.chi2 += w * r * r;
  });
}

// Point-to-point: r = s - q, J = [I, -Hat(s)] (paper eq. pt2pt), each residual seen through
// the 3x3 metric W (identity, or the degeneracy weighting of the planar analysis).
LinearSystem PointSystem(const std::vector<Correspondence>& pairs, double weight,
                         const Eigen::Matrix3d& W, double kernel_scale) {
  return ReduceDeterministic(pairs.size(), [&](std::size_t i, LinearSystem& acc) {
    const Correspondence& c = pairs[i];
    const Eigen::Vector3d r = c.source - c.target;
    Eigen::Matrix<double, 3, 6> J;
    J << Eigen::Matrix3d::Identity(), -Hat(c.source);
    const double w = weight * RobustWeight(r.squaredNorm(), kernel_scale);
    const Eigen::Matrix<double, 6, 3> JtW = J.transpose() * W;
    acc.H.noalias() += w * JtW * J;
    acc.b.noalias() += w * JtW * r;
    acc.chi2 += w * r.dot(W * r);
  });
}

// GenZ-ICP's alpha = N_pl / (N_pl + N_po); the single-residual ablations use all of one sum.
double Alpha(RegistrationMode mode, std::size_t num_planar, std::size_t num_point) {
  if (mode == RegistrationMode::kPointToPoint) return 0.0;
  if (mode == RegistrationMode::kPlaneOnly) return 1.0;
  const std::size_t n = num_planar + num_point;
  return n == 0 ? 0.0 : static_cast<double>(num_planar) / static_cast<double>(n);
}

Matrix6d Regularised(const Matrix6d& H, double relative) {
  const double scale = std::max(H.trace() / 6.0, 1e-12);
  return H + relative * scale * Matrix6d::Identity();
}

// Solution remapping: keep only the part of the translation step that lies in
// well-constrained eigen-directions.
void RemapDegenerateTranslation(const DegeneracyReport& report, Vector6d& dx) {
  dx.head<3>() -= DegenerateProjector(report) * dx.head<3>();
}

// Degeneracy weighting of a point residual: its component along eigen-direction i is scaled
// like a planar normal along it, by lambda_i / lambda_max.
Eigen::Matrix3d PointResidualMetric(const DegeneracyReport& report) {
  const double lambda_max = report.eigenvalues.maxCoeff();
  if (!(lambda_max > 0.0)) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d scale = report.eigenvalues / lambda_max;
  return report.eigenvectors * scale.asDiagonal() * report.eigenvectors.transpose();
}

// Full mode, when the planes leave a direction weak: what the point pairs (edge and unknown
// classes) say along it depends on the surface their target lies on, judged like GenZ-ICP from
// the map's 27-voxel neighbourhood. On a plane (a wall seen at grazing angles, whose rings the
// classifier calls edges) a point pair follows the ring pattern and reports standstill: it
// becomes point-to-plane. On a line (a pipe, a cable) it becomes point-to-line, two planes
// through the line. A structure (a door jamb, a lamp, an end wall's edge, a corner) keeps the
// full point residual: flattening the corners along the corridor too left a hand-held VLP-16
// walk an excursion of 1.1 m (0.097 m APE against 0.045 m). Then every planar pair counts
// along a weak direction only through a normal that faces it (|n.v| >= strong_cosine): the
// noise of a wall's normal along a corridor is not information about the axis.
struct WeakAwarePairs {
  std::vector<Correspondence> planar;
  std::vector<Correspondence> point;
};

struct LocalShape {
  int planes = 0;  // 0: a structure; 1: a plane with normal n[0]; 2: a line, normal to n[0], n[1]
  std::array<Eigen::Vector3d, 2> n;
};

LocalShape ShapeAround(const VoxelHashMap& map, const Eigen::Vector3d& target, double flatness) {
  LocalShape shape;
  const VoxelHashMap::Neighbourhood hood = map.NeighbourhoodOf(target);
  if (hood.count < 5) return shape;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(hood.covariance);
  const Eigen::Vector3d& lambda = eig.eigenvalues();  // ascending
  const double sum = lambda.sum();
  if (!(sum > 0.0)) return shape;
  shape.n = {eig.eigenvectors().col(0), eig.eigenvectors().col(1)};
  if (lambda(1) / sum < flatness) {
    shape.planes = 2;
  } else if (lambda(0) / sum < flatness) {
    shape.planes = 1;
  }
  return shape;
}

// The shape around a target depends only on its map voxel, and the map does not change during
// one registration: later iterations, and pairs landing in one voxel, reuse it.
class ShapeCache {
 public:
  ShapeCache(const VoxelHashMap& map, double flatness) : map_(map), flatness_(flatness) {}

  // The shapes around the targets of `pairs`, in their order.
  std::vector<const LocalShape*> Lookup(const std::vector<Correspondence>& pairs) {
    std::vector<Voxel> voxels(pairs.size());
    std::vector<Voxel> missing;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      voxels[i] = PointToVoxel(pairs[i].target, map_.voxel_size());
      if (shapes_.try_emplace(voxels[i]).second) missing.push_back(voxels[i]);
    }
    std::vector<LocalShape> computed(missing.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, missing.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) {
                          computed[i] = ShapeAround(map_, Centre(missing[i]), flatness_);
                        }
                      });
    for (std::size_t i = 0; i < missing.size(); ++i) shapes_[missing[i]] = computed[i];
    std::vector<const LocalShape*> out(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) out[i] = &shapes_.find(voxels[i])->second;
    return out;
  }

 private:
  Eigen::Vector3d Centre(const Voxel& v) const {
    return (v.cast<double>().array() + 0.5).matrix() * map_.voxel_size();
  }
  const VoxelHashMap& map_;
  double flatness_;
  // Node-based: pointers handed out stay valid while later lookups insert.
  std::unordered_map<Voxel, LocalShape, VoxelHash> shapes_;
};

WeakAwarePairs WeakAware(const CorrespondenceSet& pairs, const DegeneracyReport& report,
                         const RegistrationConfig& config, ShapeCache& shapes_around) {
  WeakAwarePairs out{pairs.planar, {}};
  const std::vector<const LocalShape*> shapes = shapes_around.Lookup(pairs.point);
  for (std::size_t i = 0; i < pairs.point.size(); ++i) {
    if (shapes[i]->planes == 0) {
      out.point.push_back(pairs.point[i]);
      continue;
    }
    for (int k = 0; k < shapes[i]->planes; ++k) {
      Correspondence c = pairs.point[i];
      c.normal = shapes[i]->n[static_cast<std::size_t>(k)];
      out.planar.push_back(c);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (!report.degenerate[i]) continue;
    const Eigen::Vector3d v = report.eigenvectors.col(i);
    for (Correspondence& c : out.planar) {
      const double d = c.normal.dot(v);
      if (std::abs(d) < config.strong_normal_cosine) c.normal -= d * v;
    }
  }
  return out;
}

// The motion prior as a factor on the sensor's position and orientation: residual
// [t - t_pred; log(R R_pred^T)], Jacobian [I, -Hat(t); 0, I] under the left perturbation.
void AddMotionPrior(const Eigen::Isometry3d& T, const Eigen::Isometry3d& T_pred,
                    const MotionPrior& prior, Matrix6d& H, Vector6d& b) {
  Vector6d e;
  e << T.translation() - T_pred.translation(), LogSO3(T.linear() * T_pred.linear().transpose());
  Matrix6d J = Matrix6d::Identity();
  J.topRightCorner<3, 3>() = -Hat(T.translation());
  Matrix6d information = Matrix6d::Zero();
  information.topLeftCorner<3, 3>() = prior.translation_information;
  information.bottomRightCorner<3, 3>().diagonal().setConstant(
      1.0 / (prior.rotation_sigma * prior.rotation_sigma));
  const Matrix6d JtW = J.transpose() * information;
  H.noalias() += JtW * J;
  b.noalias() += JtW * e;
}

// Freshly searched pairs pull the estimate only part of the way to where the next search
// settles: on the realistic presets successive Gauss-Newton steps point the same way and
// shrink by a ratio rho of ~0.4-0.5 per search, so the remaining way is about dx / (1 - rho)
// (Aitken's extrapolation of a geometric series; AA-ICP, Pavlov et al. 2018, accelerates ICP
// for the same reason). Only steps that repeat the previous direction are stretched, by at
// most max_factor: a step that overshoots is corrected by the next search.
Vector6d Extrapolated(const Vector6d& dx, const Vector6d& previous_dx, double max_factor) {
  constexpr double kSameDirection = 0.9;  // cosine between successive steps
  const double norm = dx.norm();
  const double previous_norm = previous_dx.norm();
  if (!(max_factor > 1.0) || !(norm > 0.0) || !(previous_norm > norm)) return dx;
  if (dx.dot(previous_dx) < kSameDirection * norm * previous_norm) return dx;
  // A step much shorter than the last is the pairs settling, not a geometric tail (which at
  // such a ratio is short anyway): stretching it would only add noise.
  constexpr double kMinRatio = 0.3;
  const double rho = norm / previous_norm;
  if (rho < kMinRatio) return dx;
  return std::min(max_factor, 1.0 / (1.0 - rho)) * dx;
}

// Returns the largest distance a point moved.
double Transform(const Eigen::Isometry3d& T, std::vector<Eigen::Vector3d>& points) {
  double moved_sq = 0.0;
  for (Eigen::Vector3d& p : points) {
    const Eigen::Vector3d q = T * p;
    moved_sq = std::max(moved_sq, (q - p).squaredNorm());
    p = q;
  }
  return std::sqrt(moved_sq);
}

void MoveSources(const Eigen::Isometry3d& T, CorrespondenceSet& pairs) {
  for (Correspondence& c : pairs.planar) c.source = T * c.source;
  for (Correspondence& c : pairs.point) c.source = T * c.source;
}

}  // namespace

RegistrationResult RegisterScan(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<PointClass>& labels, const VoxelHashMap& map,
                                const Eigen::Isometry3d& initial_guess,
                                double max_correspondence_distance, double kernel_scale,
                                const RegistrationConfig& config,
                                const MotionPrior& prior) {
  RegistrationResult result;
  result.T_world_sensor = initial_guess;
  std::vector<Eigen::Vector3d> source_world = source;
  Transform(initial_guess, source_world);
  // full_remap: the weights go with the remapping: they take the weak directions away from the
  // data, which only the held prediction can then fill. Without a trusted prediction (a start,
  // a reset, a turn the model missed) the data keeps them, unweighted.
  const bool weighted = UsesDegeneracyWeights(config.mode) &&
                        (prior.holds || !config.remap_degenerate_directions);
  const bool remap = weighted && config.remap_degenerate_directions;
  const bool fused = UsesMotionPrior(config.mode) && prior.rotation_sigma > 0.0;
  const double information_scale = 1.0 / (config.residual_sigma * config.residual_sigma);
  ShapeCache shapes_around(map, config.point_flatness);

  CorrespondenceSet pairs;
  double moved_since_search = std::numeric_limits<double>::infinity();
  Vector6d previous_dx = Vector6d::Zero();
  for (int iteration = 1; iteration <= config.max_iterations; ++iteration) {
    const bool reuse_pairs = moved_since_search < config.correspondence_reuse_distance;
    if (!reuse_pairs) {
      pairs = FindCorrespondences(source_world, labels, map, max_correspondence_distance,
                                  config.mode, config.unknown_defers_to_map);
      moved_since_search = 0.0;
      ++result.searches;
    }
    if (pairs.size() < static_cast<std::size_t>(config.min_correspondences)) break;
    result.enough_correspondences = true;

    // Paper eqs. (C_t, w_t): the point weights come from the planar correspondences alone.
    const Eigen::Matrix3d H_planar = PlanarTranslationHessian(pairs.planar);
    const DegeneracyReport planar_report = AnalyseTranslation(
        H_planar, fused ? config.weak_eigenvalue_ratio : config.degenerate_eigenvalue_ratio);
    const double alpha = Alpha(config.mode, pairs.planar.size(), pairs.point.size());
    LinearSystem system;
    if (fused && planar_report.AnyDegenerate()) {
      const WeakAwarePairs weak_aware = WeakAware(pairs, planar_report, config, shapes_around);
      system = PlanarSystem(weak_aware.planar, std::vector<double>(weak_aware.planar.size(), 1.0),
                            alpha, kernel_scale);
      system += PointSystem(weak_aware.point, 1.0 - alpha, Eigen::Matrix3d::Identity(),
                            kernel_scale);
    } else {
      // Weighting trades information for robustness; a well-conditioned scene has nothing to
      // gain from it, so by default it starts where the analysis finds a degenerate direction.
      const bool weigh = weighted && (config.weight_always || planar_report.AnyDegenerate());
      const std::vector<double> weights =
          weigh ? DegeneracyWeights(pairs.planar, planar_report)
                : std::vector<double>(pairs.planar.size(), 1.0);
      const Eigen::Matrix3d point_metric =
          weigh && config.weight_point_residuals ? PointResidualMetric(planar_report)
                                                    : Eigen::Matrix3d::Identity();
      system = PlanarSystem(pairs.planar, weights, alpha, kernel_scale);
      system += PointSystem(pairs.point, 1.0 - alpha, point_metric, kernel_scale);
    }

    const DegeneracyReport report =
        AnalyseTranslation(system.H.topLeftCorner<3, 3>(), config.degenerate_eigenvalue_ratio);
    Matrix6d H = Regularised(system.H, config.covariance_regularisation);
    Vector6d b = system.b;
    if (fused) {
      // Information in absolute units, so that it weighs against the prior's.
      H *= information_scale;
      b *= information_scale;
      result.data_information = H;
      AddMotionPrior(result.T_world_sensor, initial_guess, prior, H, b);
    }
    Vector6d dx = -H.ldlt().solve(b);
    // Remapping keeps the motion model's prediction along the directions the planes leave
    // free. Point pairs do not count there: along a corridor they follow the ring pattern
    // and report standstill. A prediction is only worth keeping once the model has held;
    // from rest or after a reset every direction is left to the data.
    if (remap && prior.holds) {
      RemapDegenerateTranslation(planar_report, dx);
    }
    if (!dx.allFinite()) break;
    const Vector6d applied =
        reuse_pairs ? dx : Extrapolated(dx, previous_dx, config.max_step_extrapolation);
    previous_dx = reuse_pairs ? Vector6d::Zero() : dx;
    const Eigen::Isometry3d step = ExpSE3(applied);
    moved_since_search += Transform(step, source_world);
    MoveSources(step, pairs);
    result.T_world_sensor = step * result.T_world_sensor;

    // Published degeneracy is the paper's analysis of the planar H_tt (what the point weights
    // use); without planar pairs, that of the whole problem.
    result.degeneracy = pairs.planar.empty() ? report : planar_report;
    result.alpha = alpha;
    result.num_planar = static_cast<std::uint32_t>(pairs.planar.size());
    result.num_point = static_cast<std::uint32_t>(pairs.point.size());
    result.iterations = iteration;
    if (fused) {
      result.covariance = H.inverse();  // absolute information: its inverse is the covariance
    } else {
      const double dof = std::max(1.0, static_cast<double>(pairs.planar.size() +
                                                           3 * pairs.point.size()) - 6.0);
      result.covariance = (system.chi2 / dof) * H.inverse();
    }
    if (dx.norm() < config.convergence_criterion) {
      result.converged = true;
      break;
    }
  }
  result.T_world_sensor = Normalized(result.T_world_sensor);
  return result;
}

}  // namespace dammloam
