#include "tools/evaluate/frame_tail.hpp"

#include "tools/evaluate/error_stats.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <random>

namespace dammloam::eval {
namespace {

// Worst over median of the norms, as the RPE statistics define both; 0 when the median is 0.
double WorstOverMedian(const std::vector<double>& norms) {
  const ErrorStats stats = ComputeStats(norms);
  return stats.median > 0.0 ? stats.max / stats.median : 0.0;
}

double Quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(position);
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double f = position - static_cast<double>(below);
  return (1.0 - f) * values[below] + f * values[above];
}

}  // namespace

FrameTail AnalyseFrameTail(const std::vector<Eigen::Vector3d>& frame_errors, int draws,
                           std::uint64_t seed) {
  FrameTail tail;
  const std::size_t n = frame_errors.size();
  if (n < 3 || draws < 1) return tail;
  std::vector<double> norms(n);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    norms[i] = frame_errors[i].norm();
    mean += frame_errors[i];
  }
  tail.worst_over_median = WorstOverMedian(norms);
  if (!(tail.worst_over_median > 0.0)) return tail;
  tail.frames = n;
  mean /= static_cast<double>(n);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& e : frame_errors) covariance += (e - mean) * (e - mean).transpose();
  covariance /= static_cast<double>(n);
  // LDLT: a run without error along one axis (planar motion) has a singular covariance.
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(covariance);
  const Eigen::Vector3d sd = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt();
  const Eigen::Matrix3d L = ldlt.transpositionsP().transpose() * Eigen::Matrix3d(ldlt.matrixL());

  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<double> ratios(static_cast<std::size_t>(draws));
  for (double& ratio : ratios) {
    for (double& norm : norms) {
      const Eigen::Vector3d z(normal(rng), normal(rng), normal(rng));
      norm = (mean + L * sd.cwiseProduct(z)).norm();
    }
    ratio = WorstOverMedian(norms);
  }
  tail.gaussian_median = Quantile(ratios, 0.5);
  tail.gaussian_p95 = Quantile(ratios, 0.95);
  tail.gaussian_share_at_least =
      static_cast<double>(std::count_if(ratios.begin(), ratios.end(), [&](double r) {
        return r >= tail.worst_over_median;
      })) / static_cast<double>(draws);
  return tail;
}

}  // namespace dammloam::eval
