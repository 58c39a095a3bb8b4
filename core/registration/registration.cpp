#include "core/registration/registration.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include "core/registration/correspondences.hpp"
#include "core/registration/degeneracy_weights.hpp"
#include "core/registration/shape_cache.hpp"

namespace dammloam {

namespace {

// Normal equations of the weighted objective; tangent order [t; r] (see degeneracy_weights.hpp)
// and, with in-scan motion, then [v; w] of the scan's own twist (N = 12; world frame, about the
// sensor position) and its angular acceleration a (N = 15).
template <int N>
struct NormalEquations {
  Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();
  Eigen::Matrix<double, N, 1> b = Eigen::Matrix<double, N, 1>::Zero();
  double chi2 = 0.0;  // weighted squared residual sum
  NormalEquations& operator+=(const NormalEquations& o) {
    H += o.H;
    b += o.b;
    chi2 += o.chi2;
    return *this;
  }
  // H is symmetric: the per-pair terms fill its lower triangle only (AddLowerTriangle), about
  // half the work of the outer products, the registration's largest cost after the search;
  // this copies it to the upper one once the sums are done.
  void MirrorLowerTriangle() {
    H.template triangularView<Eigen::StrictlyUpper>() = H.transpose().eval();
  }
};

// H += A * B on and below the diagonal, for A * B symmetric (A = w J^T W, B = J). Plain loops
// over sizes known at compile time: the compiler unrolls and vectorises them as it did Eigen's
// per-column block products, which cost a distinct product type per column (70 of this file's
// 100 s of compile time went to instantiating them).
template <int N, int R>
void AddLowerTriangle(Eigen::Matrix<double, N, N>& H, const Eigen::Matrix<double, N, R>& A,
                      const Eigen::Matrix<double, R, N>& B) {
  for (int j = 0; j < N; ++j) {
    for (int i = j; i < N; ++i) {
      double sum = A(i, 0) * B(0, j);
      for (int k = 1; k < R; ++k) sum += A(i, k) * B(k, j);
      H(i, j) += sum;
    }
  }
}
using LinearSystem = NormalEquations<6>;

// In-scan motion: a point fired tau seconds off the registered frame moves by
// tau (v + w x d) + Curve(tau) (a x d), d = p - centre (world frame, centre the sensor). The
// curve is the rotation a constant angular acceleration adds, less its mean over the scan's
// points: its constant part is the pose's rotation, not the scan's.
struct InScanBasis {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double mean_time_sq = 0.0;
  // The part of a point pair's residual that informs the angular acceleration (see
  // InScanBasisFor).
  Eigen::Matrix3d point_metric = Eigen::Matrix3d::Identity();
  double Curve(double tau) const { return 0.5 * (tau * tau - mean_time_sq); }
};

// Along a direction the planes leave weak, a point pair's residual there is what carries the
// pose (see WeakAware), ring-pattern bias included, and it must not bend the scan as well:
// tilting the scan's ends moves the floor and the ceiling along a corridor in opposite senses.
// Counted there, the acceleration and the height crawled together for the whole iteration
// budget on most scans of the endless corridor (median 41 iterations, 7 without it).
InScanBasis InScanBasisFor(const Eigen::Vector3d& centre, double mean_time_sq,
                           const DegeneracyReport* weak) {
  InScanBasis basis{centre, mean_time_sq};
  if (weak == nullptr) return basis;
  for (int i = 0; i < 3; ++i) {
    if (!weak->degenerate[i]) continue;
    const Eigen::Vector3d v = weak->eigenvectors.col(i);
    basis.point_metric -= v * v.transpose();
  }
  return basis;
}

const std::vector<float> kNoTimes;  // rigid registration: no firing times

// Geman-McClure IRLS weight, KISS-ICP's form.
double RobustWeight(double residual_sq, double kernel_scale) {
  const double d = kernel_scale + residual_sq;
  return kernel_scale * kernel_scale / (d * d);
}

// Fixed-size blocks and a deterministic reduction: the sum's rounding does not depend on
// thread scheduling, so identical inputs give bit-identical poses.
template <typename System, typename Fn>
System ReduceDeterministic(std::size_t n, Fn add_term) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, 512), System{},
      [&](const tbb::blocked_range<std::size_t>& r, System acc) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) add_term(i, acc);
        return acc;
      },
      [](System a, const System& b) { return a += b; });
}

// Point-to-plane: r = n^T (s - q), J = [n^T, (s x n)^T] (paper eq. pt2pl). Under the in-scan
// motion (InScanBasis) the twist's Jacobian is tau [n^T, (d x n)^T] and the angular
// acceleration's Curve(tau) (d x n)^T.
// One planar pair as PlanarSystem sees it: the searched pair, and the normal it counts with.
struct PlanarPairView {
  const Correspondence& pair;
  const Eigen::Vector3d& normal;
};

template <int N, typename PairAt>
NormalEquations<N> PlanarSystem(std::size_t n, PairAt pair_at, const std::vector<double>* weights,
                                double alpha, double kernel_scale, const InScanBasis& basis) {
  return ReduceDeterministic<NormalEquations<N>>(n, [&](std::size_t i, NormalEquations<N>& acc) {
    const PlanarPairView view = pair_at(i);
    const Correspondence& c = view.pair;
    const Eigen::Vector3d& normal = view.normal;
    const double r = normal.dot(c.source - c.target);
    Eigen::Matrix<double, N, 1> J;
    J.template head<6>() << normal, c.source.cross(normal);
    if constexpr (N >= 12) {
      const Eigen::Vector3d d_x_n = (c.source - basis.centre).cross(normal);
      J.template segment<6>(6) << c.time * normal, c.time * d_x_n;
      if constexpr (N == 15) J.template tail<3>() = basis.Curve(c.time) * d_x_n;
    }
    const double weight = weights != nullptr ? (*weights)[i] : 1.0;
    const double w = alpha * weight * RobustWeight(r * r, kernel_scale);
    AddLowerTriangle<N, 1>(acc.H, Eigen::Matrix<double, N, 1>(w * J), J.transpose());
    acc.b.noalias() += w * r * J;
    acc.chi2 += w * r * r;
  });
}

// Point-to-point: r = s - q, J = [I, -Hat(s)] (paper eq. pt2pt), each residual seen through
// the 3x3 metric W (identity, or the degeneracy weighting of the planar analysis).
template <int N>
NormalEquations<N> PointSystem(const std::vector<Correspondence>& pairs, double weight,
                               const Eigen::Matrix3d& W, double kernel_scale,
                               const InScanBasis& basis) {
  return ReduceDeterministic<NormalEquations<N>>(pairs.size(), [&](std::size_t i,
                                                                   NormalEquations<N>& acc) {
    const Correspondence& c = pairs[i];
    const Eigen::Vector3d r = c.source - c.target;
    Eigen::Matrix<double, 3, N> J;
    J.template leftCols<6>() << Eigen::Matrix3d::Identity(), -Hat(c.source);
    if constexpr (N >= 12) {
      const Eigen::Matrix3d d_hat = Hat(c.source - basis.centre);
      J.template middleCols<6>(6) << c.time * Eigen::Matrix3d::Identity(), -c.time * d_hat;
      if constexpr (N == 15) {
        J.template rightCols<3>() = -basis.Curve(c.time) * basis.point_metric * d_hat;
      }
    }
    const double w = weight * RobustWeight(r.squaredNorm(), kernel_scale);
    const Eigen::Matrix<double, N, 3> JtW = J.transpose() * W;
    AddLowerTriangle<N, 3>(acc.H, Eigen::Matrix<double, N, 3>(w * JtW), J);
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
// walk an excursion of 1.1 m (0.097 m APE against 0.045 m). A neighbourhood too sparse to be
// judged (a ring or two of a far wall) tells nothing about what the pair observes: it keeps its
// point residual across the weak directions and none along them. Then every planar pair counts
// along a weak direction only through a normal that faces it (|n.v| >= strong_cosine): the
// noise of a wall's normal along a corridor is not information about the axis.
// The planar pairs are the searched ones with their normals copied (and the weak components
// taken out), then the point pairs a shape made planar: copying only the normals keeps the
// searched pairs, 80 bytes each, out of a serial copy every iteration.
// (The vectors are the workspace's, refilled every iteration.)
struct WeakAwarePairs {
  const std::vector<Correspondence>& searched_planar;
  std::vector<Eigen::Vector3d>& searched_normals;
  std::vector<Correspondence>& shaped;  // point pairs turned planar by their map neighbourhood
  std::vector<Correspondence>& point;
  std::vector<Correspondence>& unjudged;  // point pairs whose map neighbourhood is too sparse

  std::size_t NumPlanar() const { return searched_normals.size() + shaped.size(); }
  Eigen::Vector3d& Normal(std::size_t j) {
    const std::size_t n = searched_normals.size();
    return j < n ? searched_normals[j] : shaped[j - n].normal;
  }
  PlanarPairView Planar(std::size_t j) const {
    const std::size_t n = searched_normals.size();
    if (j < n) return {searched_planar[j], searched_normals[j]};
    return {shaped[j - n], shaped[j - n].normal};
  }
};

// A stored normal is one pixel's estimate: near the sensor the range noise spans most of its
// tangents, and one map point in a few thousand on a corridor wall faces the axis by chance (a
// 34 deg error at 0.8 m on the hand-held VLP-16). Matched scan after scan, such a point pushed a
// sensor at rest along the endless corridor at 3 m/s. A facing pair counts along v only if its
// map neighbourhood agrees: where the neighbourhood is a judged plane that does not face v, the
// normal loses its component along v like any other wall's. Door jambs, recesses and end walls
// (structures, or planes facing v) and sparse neighbourhoods keep it.
void StripFacingNormalsOnOtherPlanes(const Eigen::Vector3d& v, double strong_cosine,
                                     const std::vector<std::size_t>& facing,
                                     RegistrationWorkspace& workspace, WeakAwarePairs& pairs) {
  if (facing.empty()) return;
  std::vector<const LocalShape*>& shapes = workspace.shapes_of_pairs;
  workspace.shapes.Lookup(
      facing.size(), [&](std::size_t k) { return pairs.searched_planar[facing[k]].target; },
      shapes);
  for (std::size_t k = 0; k < facing.size(); ++k) {
    const LocalShape& shape = *shapes[k];
    if (!shape.judged || shape.planes != 1 || std::abs(shape.n[0].dot(v)) >= strong_cosine) {
      continue;
    }
    Eigen::Vector3d& normal = pairs.searched_normals[facing[k]];
    normal -= normal.dot(v) * v;
  }
}

WeakAwarePairs WeakAware(const CorrespondenceSet& pairs, const DegeneracyReport& report,
                         const RegistrationConfig& config, RegistrationWorkspace& workspace) {
  WeakAwarePairs out{pairs.planar, workspace.searched_normals, workspace.shaped, workspace.point,
                     workspace.unjudged};
  out.searched_normals.resize(pairs.planar.size());
  out.shaped.clear();
  out.point.clear();
  out.unjudged.clear();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pairs.planar.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t j = range.begin(); j < range.end(); ++j) {
                        out.searched_normals[j] = pairs.planar[j].normal;
                      }
                    });
  std::vector<const LocalShape*>& shapes = workspace.shapes_of_pairs;
  workspace.shapes.Lookup(
      pairs.point.size(), [&](std::size_t i) { return pairs.point[i].target; }, shapes);
  for (std::size_t i = 0; i < pairs.point.size(); ++i) {
    if (!shapes[i]->judged) {
      out.unjudged.push_back(pairs.point[i]);
      continue;
    }
    if (shapes[i]->planes == 0) {
      out.point.push_back(pairs.point[i]);
      continue;
    }
    for (int k = 0; k < shapes[i]->planes; ++k) {
      Correspondence c = pairs.point[i];
      c.normal = shapes[i]->n[static_cast<std::size_t>(k)];
      out.shaped.push_back(c);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (!report.degenerate[i]) continue;
    const Eigen::Vector3d v = report.eigenvectors.col(i);
    std::vector<std::uint8_t>& faces = workspace.faces;
    faces.assign(out.NumPlanar(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.NumPlanar(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t j = range.begin(); j < range.end(); ++j) {
                          Eigen::Vector3d& normal = out.Normal(j);
                          const double d = normal.dot(v);
                          if (std::abs(d) < config.strong_normal_cosine) {
                            normal -= d * v;
                          } else {
                            faces[j] = 1;
                          }
                        }
                      });
    // Searched pairs whose stored normal faces v (a shape's pairs already carry its normal).
    std::vector<std::size_t>& facing = workspace.facing;
    facing.clear();
    for (std::size_t j = 0; j < pairs.planar.size(); ++j) {
      if (faces[j]) facing.push_back(j);
    }
    StripFacingNormalsOnOtherPlanes(v, config.strong_normal_cosine, facing, workspace, out);
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
  if (prior.rotation_information.isZero(0.0)) {
    information.bottomRightCorner<3, 3>().diagonal().setConstant(
        1.0 / (prior.rotation_sigma * prior.rotation_sigma));
  } else {
    information.bottomRightCorner<3, 3>() = prior.rotation_information;
  }
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
double StretchFactor(const Vector6d& dx, const Vector6d& previous_dx, double max_factor) {
  constexpr double kSameDirection = 0.9;  // cosine between successive steps
  const double norm = dx.norm();
  const double previous_norm = previous_dx.norm();
  if (!(max_factor > 1.0) || !(norm > 0.0) || !(previous_norm > norm)) return 1.0;
  if (dx.dot(previous_dx) < kSameDirection * norm * previous_norm) return 1.0;
  // A step much shorter than the last is the pairs settling, not a geometric tail (which at
  // such a ratio is short anyway): stretching it would only add noise.
  constexpr double kMinRatio = 0.3;
  const double rho = norm / previous_norm;
  if (rho < kMinRatio) return 1.0;
  return std::min(max_factor, 1.0 / (1.0 - rho));
}

// The in-scan unknowns: none (K = 0), the twist [v; w] (K = 6), and its angular acceleration
// a (K = 9), as departures from the deskew velocity.
template <int K>
using InScanVector = Eigen::Matrix<double, K, 1>;

// How far the in-scan motion m moves a point p fired tau seconds off the registered frame.
template <int K>
Eigen::Vector3d InScanShift(const InScanVector<K>& m, const InScanBasis& basis,
                            const Eigen::Vector3d& p, double tau) {
  const Eigen::Vector3d d = p - basis.centre;
  Eigen::Vector3d shift = tau * (m.template head<3>() + m.template segment<3>(3).cross(d));
  if constexpr (K == 9) shift += basis.Curve(tau) * m.template tail<3>().cross(d);
  return shift;
}

// The pose step, then (K > 0) the in-scan step about the new centre. Returns the largest
// distance a point moved. Run every iteration over every source point, a serial pass here was
// a tenth of the registration on two cores; a maximum is exact in any order.
template <int K>
double Transform(const Eigen::Isometry3d& T, const InScanVector<K>& in_scan_step,
                 const InScanBasis& basis, const std::vector<float>& times,
                 std::vector<Eigen::Vector3d>& points) {
  const double moved_sq = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, points.size(), 1024), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double moved) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          Eigen::Vector3d& p = points[i];
          Eigen::Vector3d q = T * p;
          if constexpr (K > 0) q += InScanShift<K>(in_scan_step, basis, q, times[i]);
          moved = std::max(moved, (q - p).squaredNorm());
          p = q;
        }
        return moved;
      },
      [](double a, double b) { return std::max(a, b); });
  return std::sqrt(moved_sq);
}

template <int K>
void MoveSources(const Eigen::Isometry3d& T, const InScanVector<K>& in_scan_step,
                 const InScanBasis& basis, CorrespondenceSet& pairs) {
  for (std::vector<Correspondence>* set : {&pairs.planar, &pairs.point}) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, set->size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i < range.end(); ++i) {
                          Correspondence& c = (*set)[i];
                          c.source = T * c.source;
                          if constexpr (K > 0) {
                            c.source += InScanShift<K>(in_scan_step, basis, c.source, c.time);
                          }
                        }
                      });
  }
}

// Full mode with a weak direction: the pairs sorted by WeakAware; lower triangle only.
template <int N>
NormalEquations<N> WeakAwareSystem(const CorrespondenceSet& pairs,
                                   const DegeneracyReport& planar_report, double alpha,
                                   double kernel_scale, const RegistrationConfig& config,
                                   RegistrationWorkspace& workspace, const InScanBasis& basis) {
  const WeakAwarePairs sorted = WeakAware(pairs, planar_report, config, workspace);
  NormalEquations<N> system, point_system, unjudged_system;
  // Together, so that the point pairs' few blocks fill the threads the planar sum leaves idle.
  tbb::parallel_invoke(
      [&] {
        system = PlanarSystem<N>(
            sorted.NumPlanar(), [&](std::size_t j) { return sorted.Planar(j); }, nullptr, alpha,
            kernel_scale, basis);
      },
      [&] {
        point_system = PointSystem<N>(sorted.point, 1.0 - alpha, Eigen::Matrix3d::Identity(),
                                      kernel_scale, basis);
      },
      [&] {
        // basis.point_metric projects the weak directions out.
        unjudged_system = PointSystem<N>(sorted.unjudged, 1.0 - alpha, basis.point_metric,
                                         kernel_scale, basis);
      });
  system += point_system;
  system += unjudged_system;
  return system;
}

// The other modes, and full mode without a weak direction: the paper's degeneracy weights
// where they apply; lower triangle only.
template <int N>
NormalEquations<N> WeightedSystem(const CorrespondenceSet& pairs,
                                  const DegeneracyReport& planar_report, bool weighted,
                                  double alpha, double kernel_scale,
                                  const RegistrationConfig& config, const InScanBasis& basis) {
  // Weighting trades information for robustness; a well-conditioned scene has nothing to
  // gain from it, so by default it starts where the analysis finds a degenerate direction.
  const bool weigh = weighted && (config.weight_always || planar_report.AnyDegenerate());
  const std::vector<double> weights =
      weigh ? DegeneracyWeights(pairs.planar, planar_report) : std::vector<double>{};
  const Eigen::Matrix3d point_metric = weigh && config.weight_point_residuals
                                           ? PointResidualMetric(planar_report)
                                           : Eigen::Matrix3d::Identity();
  NormalEquations<N> system, point_system;
  tbb::parallel_invoke(
      [&] {
        system = PlanarSystem<N>(
            pairs.planar.size(),
            [&](std::size_t j) { return PlanarPairView{pairs.planar[j], pairs.planar[j].normal}; },
            weigh ? &weights : nullptr, alpha, kernel_scale, basis);
      },
      [&] {
        point_system = PointSystem<N>(pairs.point, 1.0 - alpha, point_metric, kernel_scale, basis);
      });
  system += point_system;
  return system;
}

// The data's normal equations for this iteration's pairs (N > 6: with the in-scan motion).
template <int N>
NormalEquations<N> DataSystem(const CorrespondenceSet& pairs, const DegeneracyReport& planar_report,
                              bool weak_aware, bool weighted, double alpha, double kernel_scale,
                              const RegistrationConfig& config, RegistrationWorkspace& workspace,
                              const InScanBasis& basis) {
  NormalEquations<N> system =
      weak_aware ? WeakAwareSystem<N>(pairs, planar_report, alpha, kernel_scale, config,
                                      workspace, basis)
                 : WeightedSystem<N>(pairs, planar_report, weighted, alpha, kernel_scale, config,
                                     basis);
  system.MirrorLowerTriangle();
  return system;
}

// In-scan motion: the scan's own motion departs from the deskew velocity by `motion` so far,
// with the prior information `information` on that departure. Eliminated from the (6 + K)-
// dimensional system (Schur complement), it leaves the pose's normal equations; the pose step
// found there gives the in-scan step back.
template <int K>
class InScanElimination {
 public:
  using MatrixK = Eigen::Matrix<double, K, K>;
  InScanElimination(const NormalEquations<6 + K>& data, double scale,
                    const InScanVector<K>& motion, const MatrixK& information)
      : H_pm_(scale * data.H.template topRightCorner<6, K>()) {
    const MatrixK H_mm = scale * data.H.template bottomRightCorner<K, K>() + information;
    b_m_ = scale * data.b.template tail<K>() + information * motion;
    H_mm_.compute(H_mm);
  }
  // The pose's normal equations with the in-scan motion eliminated.
  void Eliminate(Matrix6d& H, Vector6d& b) const {
    H -= H_pm_ * H_mm_.solve(H_pm_.transpose());
    b -= H_pm_ * H_mm_.solve(b_m_);
  }
  InScanVector<K> Step(const Vector6d& pose_step) const {
    return -H_mm_.solve(b_m_ + H_pm_.transpose() * pose_step);
  }

 private:
  Eigen::Matrix<double, 6, K> H_pm_;
  InScanVector<K> b_m_;
  Eigen::LDLT<MatrixK> H_mm_;
};

// The prior's information on the in-scan motion. Along a direction the planes leave weak the
// scan cannot see its own velocity either (its pairs there are what WeakAware distrusts, and
// the in-scan term is that signal times +-half a scan): the velocity is held there. Estimated
// along the axis of the 460 m endless corridor, the pairs' ring pattern moved it scan by scan
// (APE 59.9 -> 67.5 m, RPE 0.26 -> 0.45 m).
template <int K>
Eigen::Matrix<double, K, K> InScanInformation(const MotionPrior& prior,
                                              const DegeneracyReport& planar_report,
                                              const Eigen::Vector3d& spin_axis) {
  const double v = prior.scan_velocity_sigma;
  const double w = prior.scan_rate_sigma;
  Eigen::Matrix<double, K, K> information = Eigen::Matrix<double, K, K>::Zero();
  information.diagonal().template head<6>() << Eigen::Vector3d::Constant(1.0 / (v * v)),
      Eigen::Vector3d::Constant(1.0 / (w * w));
  if constexpr (K == 9) {
    const double a = prior.scan_angular_acceleration_sigma;
    information.diagonal().template tail<3>().setConstant(1.0 / (a * a));
  }
  constexpr double kHeld = 1e4;  // times the prior's information: effectively fixed
  if constexpr (K == 9) {
    // About the spin axis an acceleration only warps the azimuths, which the scene's lateral
    // position and the ring pattern also move. Estimated there at 1 rad/s^2 it drifted the
    // wheeled VLP-16 corridor sideways (lateral APE 4 -> 15 mm); at 0.3 it halves the 1-frame
    // error outdoors but lets the hand-held corridors drift (README). So the spin axis has a
    // sigma of its own (MotionPrior::scan_spin_axis_acceleration_sigma; 0 holds it), and it is
    // held while a direction is weak: estimated there too, the warp and the weak axis crawled
    // together to the iteration cap and the estimate ran away along the 460 m endless corridor
    // on two of four runs (README).
    const double a = prior.scan_angular_acceleration_sigma;
    const double spin = prior.scan_spin_axis_acceleration_sigma;
    const bool estimated = spin > 0.0 && !planar_report.AnyDegenerate();
    const double added = estimated ? 1.0 / (spin * spin) - 1.0 / (a * a) : kHeld / (a * a);
    information.template bottomRightCorner<3, 3>() += added * spin_axis * spin_axis.transpose();
  }
  for (int i = 0; i < 3; ++i) {
    if (!planar_report.degenerate[i]) continue;
    const Eigen::Vector3d axis = planar_report.eigenvectors.col(i);
    information.template topLeftCorner<3, 3>() += kHeld / (v * v) * axis * axis.transpose();
  }
  return information;
}

// How far an in-scan step moves the scan's first and last points, at most.
template <int K>
double InScanStepLength(const InScanVector<K>& step, double max_time) {
  if constexpr (K == 0) {
    return 0.0;
  } else if constexpr (K == 6) {
    return max_time * step.norm();
  } else {
    return std::max(max_time * step.template head<6>().norm(),
                    0.5 * max_time * max_time * step.template tail<3>().norm());
  }
}

// 0: rigid scan; 6: the scan's twist; 9: its twist and angular acceleration.
int InScanUnknowns(const RegistrationConfig& config, const MotionPrior& prior,
                   const std::vector<float>& times, std::size_t num_source) {
  const bool fused = UsesMotionPrior(config.mode) && prior.rotation_sigma > 0.0;
  if (!fused || !(prior.scan_velocity_sigma > 0.0) || !(prior.scan_rate_sigma > 0.0) ||
      times.size() != num_source || num_source == 0) {
    return 0;
  }
  return prior.scan_angular_acceleration_sigma > 0.0 ? 9 : 6;
}

template <int K>
RegistrationResult Register(const std::vector<Eigen::Vector3d>& source,
                            const std::vector<PointClass>& labels, const VoxelHashMap& map,
                            const Eigen::Isometry3d& initial_guess,
                            double max_correspondence_distance, double kernel_scale,
                            const RegistrationConfig& config, const MotionPrior& prior,
                            const std::vector<float>& source_times,
                            RegistrationWorkspace& workspace) {
  RegistrationResult result;
  result.T_world_sensor = initial_guess;
  std::vector<Eigen::Vector3d>& source_world = workspace.source_world;
  source_world.assign(source.begin(), source.end());
  Transform<0>(initial_guess, {}, {}, {}, source_world);
  // full_remap: the weights go with the remapping: they take the weak directions away from the
  // data, which only the held prediction can then fill. Without a trusted prediction (a start,
  // a reset, a turn the model missed) the data keeps them, unweighted.
  const bool weighted = UsesDegeneracyWeights(config.mode) &&
                        (prior.holds || !config.remap_degenerate_directions);
  const bool remap = weighted && config.remap_degenerate_directions;
  const bool fused = UsesMotionPrior(config.mode) && prior.rotation_sigma > 0.0;
  const double information_scale = 1.0 / (config.residual_sigma * config.residual_sigma);
  workspace.shapes.Bind(map, config);
  double max_time = 0.0;  // how far a point's time lies from the registered frame's
  double mean_time_sq = 0.0;
  if constexpr (K > 0) {
    for (float t : source_times) max_time = std::max(max_time, std::abs(double{t}));
  }
  if constexpr (K == 9) {
    for (float t : source_times) mean_time_sq += double{t} * t;
    mean_time_sq /= static_cast<double>(source_times.size());
  }
  InScanVector<K> motion = InScanVector<K>::Zero();  // departure from the deskew velocity

  CorrespondenceSet& pairs = workspace.pairs;
  SearchMemory& search_memory = workspace.search_memory;
  search_memory.Reset(source_world.size());
  double moved_since_search = std::numeric_limits<double>::infinity();
  Vector6d previous_dx = Vector6d::Zero();
  // Coarse to fine: the first searches pair every coarse_stride-th source point only. The
  // prediction is off by centimetres, so those first steps need the direction, not every
  // point; once a coarse step settles, every point is paired for the remaining (short) way.
  // The settled coarse pairs are as fresh as the reuse rule asks, so that first full search
  // looks up only the other points.
  const std::size_t coarse_stride = static_cast<std::size_t>(std::max(1, config.coarse_stride));
  bool coarse = coarse_stride > 1;
  CorrespondenceSet& settled_coarse_pairs = workspace.settled_coarse_pairs;
  // How far the settled pairs' sources moved since they were found; infinite: none settled.
  double settled_moved = std::numeric_limits<double>::infinity();
  const auto end_coarse_phase = [&](bool settled) {
    coarse = false;
    if (settled) {
      std::swap(settled_coarse_pairs, pairs);  // pairs is searched again before any use
      settled_moved = moved_since_search;
    }
    moved_since_search = std::numeric_limits<double>::infinity();  // search every point next
    previous_dx.setZero();  // the next step corrects the subset's optimum: not a continuation
  };
  for (int iteration = 1; iteration <= config.max_iterations; ++iteration) {
    const bool reuse_pairs = moved_since_search < config.correspondence_reuse_distance;
    if (!reuse_pairs) {
      const bool add_settled = !coarse && std::isfinite(settled_moved);
      const SourceSubset subset{coarse || add_settled ? coarse_stride : 1, add_settled};
      FindCorrespondences(source_world, labels, map, max_correspondence_distance, config.mode,
                          config.unknown_defers_to_map, K > 0 ? source_times : kNoTimes, subset,
                          &search_memory, workspace.search_buffers, pairs);
      moved_since_search = 0.0;
      ++result.searches;
      result.searched_points += pairs.searched_points;
      if (add_settled) {
        for (auto [to, from] : {std::pair{&pairs.planar, &settled_coarse_pairs.planar},
                                std::pair{&pairs.point, &settled_coarse_pairs.point}}) {
          to->insert(to->end(), from->begin(), from->end());
        }
        moved_since_search = settled_moved;
        settled_moved = std::numeric_limits<double>::infinity();
      }
    }
    if (coarse && pairs.size() < static_cast<std::size_t>(config.min_correspondences)) {
      end_coarse_phase(false);
      continue;
    }
    if (pairs.size() < static_cast<std::size_t>(config.min_correspondences)) break;
    result.enough_correspondences = true;

    // Paper eqs. (C_t, w_t): the point weights come from the planar correspondences alone.
    const Eigen::Matrix3d H_planar = PlanarTranslationHessian(pairs.planar);
    const DegeneracyReport planar_report = AnalyseTranslation(
        H_planar, fused ? config.weak_eigenvalue_ratio : config.degenerate_eigenvalue_ratio);
    const double alpha = Alpha(config.mode, pairs.planar.size(), pairs.point.size());
    const bool weak_aware =
        fused && (config.judge_point_pairs_always || planar_report.AnyDegenerate());
    if (coarse && planar_report.AnyDegenerate()) {
      // Along a weak direction the few pairs facing it (a jamb, an end wall) are what observe
      // it, and a subset may miss them: the coarse pose then slid along the endless
      // corridor's axis, and the pairs searched there stuck (VLP-16 APE 48.9 -> 68.1 m).
      // These pairs were just searched: the full search keeps them and adds the others.
      // (Full mode: weak directions; the other modes: degenerate ones.)
      end_coarse_phase(true);
      continue;
    }
    const InScanBasis basis = InScanBasisFor(result.T_world_sensor.translation(), mean_time_sq,
                                             weak_aware ? &planar_report : nullptr);
    LinearSystem system;
    // A coarse pair stands for coarse_stride points: the data weigh against the prior as if all
    // had been paired.
    const double pair_information =
        information_scale * (coarse ? static_cast<double>(coarse_stride) : 1.0);
    std::optional<InScanElimination<K>> in_scan;
    if constexpr (K > 0) {
      const NormalEquations<6 + K> full = DataSystem<6 + K>(
          pairs, planar_report, weak_aware, weighted, alpha, kernel_scale, config, workspace,
          basis);
      system.H = full.H.template topLeftCorner<6, 6>();
      system.b = full.b.template head<6>();
      system.chi2 = full.chi2;
      in_scan.emplace(full, pair_information, motion,
                      InScanInformation<K>(prior, planar_report,
                                           result.T_world_sensor.linear().col(2)));
    } else {
      system = DataSystem<6>(pairs, planar_report, weak_aware, weighted, alpha, kernel_scale,
                             config, workspace, basis);
    }

    const DegeneracyReport report =
        AnalyseTranslation(system.H.topLeftCorner<3, 3>(), config.degenerate_eigenvalue_ratio);
    Matrix6d H = Regularised(system.H, config.covariance_regularisation);
    Vector6d b = system.b;
    if (fused) {
      // Information in absolute units, so that it weighs against the prior's.
      H *= pair_information;
      b *= pair_information;
      if (in_scan) in_scan->Eliminate(H, b);
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
    const InScanVector<K> motion_dx = in_scan ? in_scan->Step(dx) : InScanVector<K>::Zero();
    if (!dx.allFinite() || !motion_dx.allFinite()) break;
    const double stretch =
        reuse_pairs ? 1.0 : StretchFactor(dx, previous_dx, config.max_step_extrapolation);
    const Vector6d applied = stretch * dx;
    previous_dx = reuse_pairs ? Vector6d::Zero() : dx;
    const Eigen::Isometry3d step = ExpSE3(applied);
    result.T_world_sensor = step * result.T_world_sensor;
    const InScanVector<K> motion_step = stretch * motion_dx;
    const InScanBasis moved_basis{result.T_world_sensor.translation(), mean_time_sq};
    moved_since_search += Transform<K>(step, motion_step, moved_basis, source_times, source_world);
    MoveSources<K>(step, motion_step, moved_basis, pairs);
    motion += motion_step;

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
    const bool converged = dx.norm() < config.convergence_criterion &&
                           InScanStepLength<K>(motion_dx, max_time) < config.convergence_criterion;
    if (coarse) {
      // Settled: the next iteration would keep these pairs, or the subset has converged.
      if (converged || moved_since_search < config.correspondence_reuse_distance) {
        end_coarse_phase(moved_since_search < config.correspondence_reuse_distance);
      }
      continue;
    }
    if (converged) {
      result.converged = true;
      break;
    }
  }
  result.T_world_sensor = Normalized(result.T_world_sensor);
  const Eigen::Matrix3d Rt = result.T_world_sensor.linear().transpose();
  if constexpr (K > 0) {
    result.scan_twist << Rt * motion.template head<3>(), Rt * motion.template segment<3>(3);
  }
  if constexpr (K == 9) {
    result.scan_angular_acceleration = Rt * motion.template tail<3>();
    result.scan_mean_time_sq = mean_time_sq;
  }
  return result;
}

}  // namespace

Eigen::Matrix3d RegistrationResult::PositionInformation() const {
  const Matrix6d& I = data_information;
  return I.topLeftCorner<3, 3>() -
         I.topRightCorner<3, 3>() * I.bottomRightCorner<3, 3>().ldlt().solve(I.bottomLeftCorner<3, 3>());
}

RegistrationResult RegisterScan(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<PointClass>& labels, const VoxelHashMap& map,
                                const Eigen::Isometry3d& initial_guess,
                                double max_correspondence_distance, double kernel_scale,
                                const RegistrationConfig& config,
                                const MotionPrior& prior,
                                const std::vector<float>& source_times,
                                RegistrationWorkspace* workspace) {
  // Odometry passes the workspace it keeps across scans; a caller without one gets one for this
  // scan only.
  std::optional<RegistrationWorkspace> this_scan_only;
  if (workspace == nullptr) workspace = &this_scan_only.emplace();
  switch (InScanUnknowns(config, prior, source_times, source.size())) {
    case 9:
      return Register<9>(source, labels, map, initial_guess, max_correspondence_distance,
                         kernel_scale, config, prior, source_times, *workspace);
    case 6:
      return Register<6>(source, labels, map, initial_guess, max_correspondence_distance,
                         kernel_scale, config, prior, source_times, *workspace);
    default:
      return Register<0>(source, labels, map, initial_guess, max_correspondence_distance,
                         kernel_scale, config, prior, source_times, *workspace);
  }
}

}  // namespace dammloam
