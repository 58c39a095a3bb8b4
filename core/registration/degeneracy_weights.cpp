#include "core/registration/degeneracy_weights.hpp"

#include <Eigen/Eigenvalues>

namespace dammloam {

Eigen::Matrix3d PlanarTranslationHessian(const std::vector<Correspondence>& planar) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (const Correspondence& c : planar) H.noalias() += c.normal * c.normal.transpose();
  return H;
}

DegeneracyReport AnalyseTranslation(const Eigen::Matrix3d& H_tt, double ratio_threshold) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(H_tt);
  DegeneracyReport report;
  report.eigenvalues = solver.eigenvalues().cwiseMax(0.0);
  report.eigenvectors = solver.eigenvectors();
  const double lambda_max = report.eigenvalues.maxCoeff();
  for (int i = 0; i < 3; ++i) {
    report.degenerate[i] = lambda_max <= 0.0 || report.eigenvalues[i] < ratio_threshold * lambda_max;
  }
  return report;
}

std::vector<double> DegeneracyWeights(const std::vector<Correspondence>& planar,
                                      const DegeneracyReport& report) {
  const double lambda_max = report.eigenvalues.maxCoeff();
  std::vector<double> weights(planar.size(), 1.0);
  if (lambda_max <= 0.0) return weights;
  const Eigen::Vector3d lambda_normalised = report.eigenvalues / lambda_max;
  for (std::size_t i = 0; i < planar.size(); ++i) {
    const Eigen::Vector3d contribution =
        (report.eigenvectors.transpose() * planar[i].normal).cwiseAbs();
    weights[i] = contribution.cwiseProduct(lambda_normalised).norm();
  }
  return weights;
}

Eigen::Matrix3d DegenerateProjector(const DegeneracyReport& report) {
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < 3; ++i) {
    if (!report.degenerate[i]) continue;
    const Eigen::Vector3d v = report.eigenvectors.col(static_cast<Eigen::Index>(i));
    P.noalias() += v * v.transpose();
  }
  return P;
}

}  // namespace dammloam
