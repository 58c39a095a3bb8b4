// What the pose graph's odometry edges weigh: the front end's covariances composed in the edge's
// frame.
#include <gtest/gtest.h>

#include <cmath>

#include "core/backend/loop_closing_backend.hpp"
#include "tests/backend/sim_run.hpp"

namespace dammloam::backend {
namespace {

// Scans 0.11 m apart along the body's x axis (a keyframe every 10: 1.1 m, clear of the 1 m
// threshold), starting at `start`, each with the same body-frame covariance reported as the
// front end does (world-frame left perturbation).
std::vector<Matrix6d> EdgeCovariances(const Eigen::Isometry3d& start, const Matrix6d& body) {
  BackendConfig config;
  config.max_verifications_per_keyframe = 0;  // edges only
  LoopClosingBackend backend(config);
  for (int i = 0; i < 40; ++i) {
    OdometryResult r;
    r.scan_index = static_cast<std::uint64_t>(i);
    r.stamp = 0.1 * i;
    r.T_world_sensor = start * Eigen::Translation3d(0.11 * i, 0.0, 0.0);
    r.covariance = test::WorldCovariance(body, r.T_world_sensor);
    for (int k = 0; k < 50; ++k) {
      r.deskewed_points.emplace_back(5.0 * std::cos(0.13 * k), 5.0 * std::sin(0.13 * k), 0.1 * k);
    }
    backend.AddScan(r);
  }
  backend.Process();
  std::vector<Matrix6d> edges;
  for (const Keyframe& kf : backend.ExportMap().keyframes) edges.push_back(kf.edge_covariance);
  return edges;
}

TEST(OdometryEdges, CovarianceIsTheSameMotionsWhereverItHappens) {
  Matrix6d body = Matrix6d::Zero();
  body.diagonal() << 4e-6, 1e-6, 2e-6, 1e-8, 2e-8, 3e-8;
  body(0, 5) = body(5, 0) = 1e-7;
  const std::vector<Matrix6d> near = EdgeCovariances(Eigen::Isometry3d::Identity(), body);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translate(Eigen::Vector3d(150.0, -80.0, 3.0));
  far.rotate(Eigen::AngleAxisd(1.9, Eigen::Vector3d::UnitZ()));
  const std::vector<Matrix6d> moved = EdgeCovariances(far, body);
  ASSERT_GE(near.size(), 3u);  // a keyframe per metre
  ASSERT_EQ(near.size(), moved.size());
  for (std::size_t k = 1; k < near.size(); ++k) {
    // Straight motion: every scan's covariance is in the edge's frame already, so an edge over
    // n scans holds n of them, 150 m from the origin as next to it.
    EXPECT_TRUE(near[k].isApprox(10.0 * body, 1e-9)) << "edge " << k << "\n" << near[k];
    EXPECT_TRUE(moved[k].isApprox(near[k], 1e-6)) << "edge " << k << "\n" << moved[k];
  }
}

}  // namespace
}  // namespace dammloam::backend
