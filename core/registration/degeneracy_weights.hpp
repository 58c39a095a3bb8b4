#pragma once
#include <Eigen/Core>
#include <vector>

#include "core/odometry/odometry_result.hpp"
#include "core/registration/correspondences.hpp"

namespace dammloam {

// Jacobian parameter order, everywhere in registration/: x = [t; r] (translation first, as in
// core/geometry/se3.hpp), perturbation applied on the left in the world frame:
//   T <- ExpSE3(x) * T,   d(p_world)/dx = [ I  -Hat(p_world) ].
// The translational Hessian block H_tt is therefore H.topLeftCorner<3,3>(); for a
// point-to-plane pair it is n n^T.

// Translational Hessian of the planar pairs, H_tt = sum n n^T = I_t^T I_t (paper eqs.
// h_tt_eigen, information_matrix).
Eigen::Matrix3d PlanarTranslationHessian(const std::vector<Correspondence>& planar);

// Eigen-decomposition H_tt = V_t Sigma_t V_t^T (ascending eigenvalues, eigenvectors as columns
// in the world frame); a direction is degenerate when lambda_i / lambda_max < ratio_threshold.
DegeneracyReport AnalyseTranslation(const Eigen::Matrix3d& H_tt, double ratio_threshold);

// Projector onto the span of the degenerate translational directions (zero if none): what the
// remapping drops from a step, and where the odometry lets uncertainty build up.
Eigen::Matrix3d DegenerateProjector(const DegeneracyReport& report);

// Paper eqs. observability_score, weighted_observability, weight_computation:
// C_t = |I_t V_t|, columns scaled by lambda_i / lambda_max, w_i = ||row_i||_2 in [0, 1].
std::vector<double> DegeneracyWeights(const std::vector<Correspondence>& planar,
                                      const DegeneracyReport& report);

}  // namespace dammloam
