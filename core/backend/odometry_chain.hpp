#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/backend/keyframe.hpp"
#include "core/geometry/se3.hpp"

namespace dammloam::backend {

// What odometry alone says about the relative pose of two keyframes: its value and how
// uncertain the chain of odometry edges between them makes it.
struct OdometryChain {
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  // In the pose graph's edge tangent: translation in `from`'s frame, rotation right-perturbed.
  Matrix6d covariance = Matrix6d::Zero();
};

// What the odometry edges' own covariances leave out. Floors are added to each edge (as the pose
// graph does), so that a chain of over-confident registrations counts as uncertain as the graph
// treats it. Registration errors are not independent from scan to scan: a heading bias turns
// every edge the same way, so the heading error grows with the distance travelled and its
// position error with the square of it; the scans' covariances, summed as if independent,
// miss that (a 1.2 km drive: 4.6 deg of heading drift against 0.37 deg of summed sigma).
struct ChainNoise {
  double translation_sigma = 0.0;        // metres per edge
  double rotation_sigma = 0.0;           // radians per edge
  double heading_drift_per_metre = 0.0;  // radians per metre: one sigma of a heading-rate bias
};

// Composes the odometry edges of keyframes from+1..to (keyframes[k].edge_covariance is the
// edge k-1 -> k) to first order. The rotation uncertainty of early edges grows into position
// uncertainty through the lever arm of the rest of the chain. The heading bias turns about the
// odometry world's vertical.
OdometryChain ComposeOdometryChain(const std::vector<Keyframe>& keyframes, std::uint32_t from,
                                   std::uint32_t to, const ChainNoise& noise);

// Squared Mahalanobis distance of a measured relative position from odometry's, under the sum
// of both covariances' position blocks (3 degrees of freedom). Position only: where the heading
// drifted is not known (a bias, or one bad turn), and the two put the heading error and the
// position error in different proportions; a joint test would refuse true loops after a turn.
// The rotation is judged by the loop verifier's own budget.
double ConsistencyChi2(const OdometryChain& odometry, const Eigen::Isometry3d& T_measured,
                       const Matrix6d& measured_covariance);

}  // namespace dammloam::backend
