#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/backend/pose_graph.hpp"

namespace dammloam::backend {
namespace {

// A 20 m x 20 m square driven once (1 m steps, 90 degree turns at the corners) and back to start.
std::vector<Eigen::Isometry3d> SquareTruth() {
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  poses.push_back(T);
  for (int side = 0; side < 4; ++side) {
    for (int step = 0; step < 20; ++step) {
      Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
      delta.translation().x() = 1.0;
      if (step == 19) {
        delta.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ())
                             .toRotationMatrix();
      }
      T = T * delta;
      poses.push_back(T);
    }
  }
  return poses;  // last pose coincides with the first (position and heading)
}

struct Drifted {
  std::vector<Eigen::Isometry3d> measured_steps;
  std::vector<Eigen::Isometry3d> integrated;
};

constexpr double kNoiseSigma = 0.01;  // metres per step

Drifted DriftedOdometry(const std::vector<Eigen::Isometry3d>& truth) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, kNoiseSigma);
  Drifted d;
  d.integrated.push_back(truth.front());
  for (std::size_t i = 1; i < truth.size(); ++i) {
    Eigen::Isometry3d step = truth[i - 1].inverse() * truth[i];
    step.translation() += Eigen::Vector3d(noise(rng), noise(rng), 0.0);
    // A systematic yaw bias (0.17 deg/m), the dominant drift of real odometry.
    step.linear() = Eigen::AngleAxisd(0.003 + noise(rng) * 0.1, Eigen::Vector3d::UnitZ())
                        .toRotationMatrix() * step.linear();
    d.measured_steps.push_back(step);
    d.integrated.push_back(d.integrated.back() * step);
  }
  return d;
}

double PositionRmse(const PoseGraph& graph, const std::vector<Eigen::Isometry3d>& truth) {
  double sum = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    sum += (graph.Pose(static_cast<std::uint32_t>(i)).translation() - truth[i].translation())
               .squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(truth.size()));
}

PoseGraph BuildOdometryGraph(const Drifted& d) {
  PoseGraph graph;
  for (const auto& T : d.integrated) graph.AddNode(T);
  Matrix6d covariance = Matrix6d::Zero();
  covariance.diagonal() << 1e-4, 1e-4, 1e-4, 1e-5, 1e-5, 1e-5;
  for (std::size_t i = 0; i < d.measured_steps.size(); ++i) {
    graph.AddOdometryEdge(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1),
                          d.measured_steps[i], covariance);
  }
  return graph;
}

Matrix6d LoopCovariance() {
  Matrix6d c = Matrix6d::Zero();
  c.diagonal() << 0.0025, 0.0025, 0.0025, 1e-4, 1e-4, 1e-4;
  return c;
}

TEST(PoseGraph, TrueLoopReducesApeAtLeastTwofold) {
  const auto truth = SquareTruth();
  const Drifted d = DriftedOdometry(truth);
  PoseGraph graph = BuildOdometryGraph(d);
  const double before = PositionRmse(graph, truth);
  const auto last = static_cast<std::uint32_t>(truth.size() - 1);
  graph.AddLoopEdge(0, last, truth.front().inverse() * truth.back(), LoopCovariance());
  const PoseGraphSummary summary = graph.Optimize();
  const double after = PositionRmse(graph, truth);
  std::printf("square loop APE RMSE: odometry %.3f m, optimised %.3f m (%.1f ms)\n", before, after,
              summary.solve_ms);
  EXPECT_GT(before, 1.0);  // the drift is real
  EXPECT_LT(after * 2.0, before);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_EQ(summary.rejected_loops, 0);
  std::printf("loop residual (whitened) %.3f\n", graph.LoopResiduals().at(0));
  EXPECT_TRUE(graph.Pose(0).isApprox(truth.front(), 1e-9));  // node 0 held fixed
}

TEST(PoseGraph, InjectedFalseLoopMovesTrajectoryLessThanTheNoise) {
  const auto truth = SquareTruth();
  const Drifted d = DriftedOdometry(truth);
  const auto last = static_cast<std::uint32_t>(truth.size() - 1);
  PoseGraph good = BuildOdometryGraph(d);
  good.AddLoopEdge(0, last, truth.front().inverse() * truth.back(), LoopCovariance());
  good.Optimize();

  PoseGraph attacked = BuildOdometryGraph(d);
  attacked.AddLoopEdge(0, last, truth.front().inverse() * truth.back(), LoopCovariance());
  // Claims that node 30 (on side two) is node 70 (side four) shifted: a 10+ m lie.
  Eigen::Isometry3d lie = truth[30].inverse() * truth[70];
  lie.translation() += Eigen::Vector3d(4.0, -3.0, 0.0);
  attacked.AddLoopEdge(30, 70, lie, LoopCovariance());
  const PoseGraphSummary summary = attacked.Optimize();
  const auto residuals = attacked.LoopResiduals();
  std::printf("loop residuals (whitened): true %.3f, false %.3f\n", residuals.at(0),
              residuals.at(1));
  EXPECT_EQ(summary.rejected_loops, 1);
  EXPECT_EQ(attacked.NumRejectedLoops(), 1u);

  double max_shift = 0;
  for (std::uint32_t i = 0; i <= last; ++i) {
    max_shift = std::max(max_shift, (attacked.Pose(i).translation() - good.Pose(i).translation())
                                        .norm());
  }
  std::printf("false loop moved the trajectory by at most %.4f m (noise %.3f m/step)\n",
              max_shift, kNoiseSigma);
  EXPECT_LT(max_shift, kNoiseSigma);
}

TEST(PoseGraph, RejectsEdgesToUnknownNodes) {
  PoseGraph graph;
  graph.AddNode(Eigen::Isometry3d::Identity());
  EXPECT_THROW(graph.AddOdometryEdge(0, 3, Eigen::Isometry3d::Identity(), Matrix6d::Identity()),
               std::out_of_range);
}

}  // namespace
}  // namespace dammloam::backend
