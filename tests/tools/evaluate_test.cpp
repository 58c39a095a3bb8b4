#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <stack>

#include "core/geometry/se3.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tools/evaluate/metrics_report.hpp"
#include "tools/evaluate/svg_plot.hpp"
#include "tools/evaluate/trajectory_metrics.hpp"

namespace dammloam::eval {
namespace {

Eigen::Isometry3d Pose(const Eigen::Vector3d& t, const Eigen::Vector3d& rotation_vector = Eigen::Vector3d::Zero()) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = ExpSO3(rotation_vector);
  T.translation() = t;
  return T;
}

// A curving, climbing, turning trajectory: 40 poses, 0.1 s apart.
std::vector<StampedPose> Helix() {
  std::vector<StampedPose> poses;
  for (int i = 0; i < 40; ++i) {
    const double a = 0.15 * i;
    poses.push_back({100.0 + 0.1 * i,
                     Pose({5.0 * std::cos(a), 5.0 * std::sin(a), 0.05 * i}, {0.02 * i, -0.01, a})});
  }
  return poses;
}

std::vector<StampedPose> Positions(const std::vector<Eigen::Vector3d>& points) {
  std::vector<StampedPose> poses;
  for (std::size_t i = 0; i < points.size(); ++i) poses.push_back({0.1 * i, Pose(points[i])});
  return poses;
}

TEST(EvaluateTrajectories, RigidOffsetGivesZeroErrorAfterAlignment) {
  const auto gt = Helix();
  const Eigen::Isometry3d offset = Pose({12.0, -3.0, 1.5}, {0.3, -0.2, 1.1});
  std::vector<StampedPose> est = gt;
  for (auto& pose : est) pose.T = offset * pose.T;

  const TrajectoryMetrics m = EvaluateTrajectories(gt, est);
  EXPECT_EQ(m.pairs, 40u);
  EXPECT_LT(m.ape.rmse, 1e-9);
  EXPECT_LT(m.ape.max, 1e-9);
  EXPECT_TRUE(m.alignment.isApprox(offset.inverse(), 1e-9));
  EXPECT_LT(m.rpe.max, 1e-9);  // a world-frame offset does not change relative motion
  EXPECT_LT(m.end_drift_m, 1e-9);
  EXPECT_GT(m.path_length_m, 25.0);
}

TEST(EvaluateTrajectories, ConstantPerFrameDriftShowsInRpeAndDrift) {
  const double d = 0.03, step = 1.0;
  std::vector<StampedPose> gt, est;
  Eigen::Isometry3d est_pose = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 21; ++i) {
    gt.push_back({0.1 * i, Pose({step * i, 0.0, 0.0})});
    if (i > 0) est_pose = est_pose * Pose({step + d, 0.0, 0.0});
    est.push_back({0.1 * i, est_pose});
  }
  const TrajectoryMetrics m = EvaluateTrajectories(gt, est);
  EXPECT_NEAR(m.rpe.mean, d, 1e-12);
  EXPECT_NEAR(m.rpe.std, 0.0, 1e-12);
  EXPECT_EQ(m.rpe.count, 20u);
  EXPECT_NEAR(m.path_length_m, 20.0, 1e-12);
  EXPECT_NEAR(m.end_drift_m, 20 * d, 1e-12);
  EXPECT_NEAR(m.drift_percent, 100.0 * d / step, 1e-9);
}

// Straight gt; est deviates so that per-frame errors are 0.1, 0.2, 0.2 m (by hand).
TEST(EvaluateTrajectories, HandComputedRpeAndDrift) {
  const auto gt = Positions({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  const auto est = Positions({{0, 0, 0}, {1.1, 0, 0}, {2.1, 0.2, 0}, {3.3, 0.2, 0}});
  const TrajectoryMetrics m = EvaluateTrajectories(gt, est);
  EXPECT_NEAR(m.rpe.mean, 0.5 / 3.0, 1e-12);
  EXPECT_NEAR(m.rpe.median, 0.2, 1e-12);
  EXPECT_NEAR(m.rpe.min, 0.1, 1e-12);
  EXPECT_NEAR(m.rpe.max, 0.2, 1e-12);
  EXPECT_NEAR(m.rpe.rmse, std::sqrt(0.03), 1e-12);
  EXPECT_NEAR(m.rpe.std, std::sqrt((std::pow(0.1 - 0.5 / 3, 2) + 2 * std::pow(0.2 - 0.5 / 3, 2)) / 3), 1e-12);
  EXPECT_NEAR(m.rpe.sse, 0.09, 1e-12);
  EXPECT_NEAR(m.path_length_m, 3.0, 1e-12);
  EXPECT_NEAR(m.end_drift_m, std::sqrt(0.09 + 0.04), 1e-12);
  EXPECT_NEAR(m.drift_percent, 100.0 * std::sqrt(0.13) / 3.0, 1e-9);
}

// est = a rigid motion of gt scaled by 1.1 about its centroid: the SE(3) alignment undoes the
// motion and leaves errors of 0.1 * (distance to the centroid), computed by hand.
TEST(EvaluateTrajectories, HandComputedApeAfterAlignment) {
  const std::vector<Eigen::Vector3d> corners = {{0, 0, 0}, {4, 0, 0}, {4, 2, 0}, {0, 1, 0}};
  const Eigen::Vector3d centroid(2.0, 0.75, 0.0);
  const Eigen::Isometry3d motion = Pose({-7.0, 3.0, 2.0}, {0.0, 0.0, 0.5});
  std::vector<Eigen::Vector3d> moved;
  for (const auto& c : corners) moved.push_back(motion * (centroid + 1.1 * (c - centroid)));
  const TrajectoryMetrics m = EvaluateTrajectories(Positions(corners), Positions(moved));
  // Squared distances to the centroid: 4.5625, 4.5625, 5.5625, 4.0625.
  const double e0 = 0.1 * std::sqrt(4.5625), e2 = 0.1 * std::sqrt(5.5625), e3 = 0.1 * std::sqrt(4.0625);
  EXPECT_NEAR(m.ape.max, e2, 1e-9);
  EXPECT_NEAR(m.ape.min, e3, 1e-9);
  EXPECT_NEAR(m.ape.mean, (2 * e0 + e2 + e3) / 4, 1e-9);
  EXPECT_NEAR(m.ape.median, e0, 1e-9);
  EXPECT_NEAR(m.ape.rmse, 0.1 * std::sqrt((2 * 4.5625 + 5.5625 + 4.0625) / 4), 1e-9);
  EXPECT_TRUE(m.alignment.isApprox(motion.inverse(), 1e-9));
}

TEST(EvaluateTrajectories, UnmatchedTimestampsAreSkipped) {
  std::vector<StampedPose> gt, est;
  for (int i = 0; i < 10; ++i) gt.push_back({1.0 + 0.1 * i, Pose({1.0 * i, 0, 0})});
  for (int i = 0; i < 10; ++i) {
    if (i == 4) continue;                                       // est misses one scan
    const double jitter = (i == 7) ? 0.03 : 0.004;              // one too far off to pair
    est.push_back({1.0 + 0.1 * i + jitter, Pose({1.0 * i, 0, 0})});
  }
  est.push_back({5.0, Pose({50, 0, 0})});                       // beyond the gt
  const TrajectoryMetrics m = EvaluateTrajectories(gt, est);
  EXPECT_EQ(m.pairs, 8u);
  EXPECT_EQ(m.unmatched_gt, 2u);
  EXPECT_EQ(m.unmatched_est, 2u);
  EXPECT_LT(m.ape.max, 1e-9);

  EvaluateOptions loose;
  loose.max_time_diff = 0.035;
  EXPECT_EQ(EvaluateTrajectories(gt, est, loose).pairs, 9u);
}

TEST(EvaluateTrajectories, AssociationTakesTheNearestPoseOnce) {
  const std::vector<StampedPose> gt = {{1.0, Pose({0, 0, 0})}, {2.0, Pose({1, 0, 0})}};
  const std::vector<StampedPose> est = {{2.004, Pose({9, 0, 0})}, {0.995, Pose({0, 0, 0})},
                                        {1.999, Pose({1, 0, 0})}, {1.002, Pose({8, 0, 0})}};
  const MatchedTrajectories matched = AssociateByTime(gt, est, 0.01);
  ASSERT_EQ(matched.gt.size(), 2u);
  EXPECT_EQ(matched.est[0].t, 1.002);
  EXPECT_EQ(matched.est[1].t, 1.999);
}

TEST(EvaluateTrajectories, TooFewPairsIsAnError) {
  const auto gt = Positions({{0, 0, 0}, {1, 0, 0}});
  auto est = gt;
  for (auto& pose : est) pose.t += 10.0;
  EXPECT_THROW(EvaluateTrajectories(gt, est), std::invalid_argument);
}

TEST(MetricsReport, JsonHasTheDocumentedKeys) {
  const auto gt = Helix();
  auto est = gt;
  for (auto& pose : est) pose.T.translation().x() += 0.1;
  const auto json = nlohmann::json::parse(FormatJson(EvaluateTrajectories(gt, est)));
  for (const char* key : {"ape", "rpe", "drift_percent", "path_length_m", "pairs", "alignment"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  for (const char* key : {"mean", "max", "median", "rmse", "std", "min"}) {
    EXPECT_TRUE(json["ape"].contains(key)) << key;
    EXPECT_TRUE(json["rpe"].contains(key)) << key;
  }
  EXPECT_EQ(json["pairs"], 40);
  EXPECT_NEAR(json["ape"]["max"].get<double>(), 0.0, 1e-9);
  const std::string table = FormatTable(EvaluateTrajectories(gt, est));
  EXPECT_NE(table.find("APE"), std::string::npos);
  EXPECT_NE(table.find("RPE"), std::string::npos);
}

// Minimal well-formedness: every opened element is closed in order (attributes hold no '<').
bool TagsBalanced(const std::string& text) {
  std::stack<std::string> open;
  for (std::size_t pos = text.find('<'); pos != std::string::npos; pos = text.find('<', pos + 1)) {
    const std::size_t end = text.find('>', pos);
    if (end == std::string::npos) return false;
    const std::string tag = text.substr(pos + 1, end - pos - 1);
    if (tag.empty()) return false;
    if (tag.back() == '/') continue;
    const std::string name = tag.substr(tag[0] == '/' ? 1 : 0, tag.find_first_of(" \n") - (tag[0] == '/' ? 1 : 0));
    if (tag[0] != '/') {
      open.push(name);
    } else {
      if (open.empty() || open.top() != name) return false;
      open.pop();
    }
  }
  return open.empty();
}

TEST(SvgPlot, WritesWellFormedTopView) {
  test::TempDir tmp;
  const auto gt = Helix();
  auto est = gt;
  for (auto& pose : est) pose.T.translation().y() += 0.2;
  const TrajectoryMetrics m = EvaluateTrajectories(gt, est);
  WriteTopViewSvg(tmp / "plot.svg", m.gt_positions, m.est_positions_aligned);
  const std::string svg = test::ReadText(tmp / "plot.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_TRUE(TagsBalanced(svg));
  std::size_t polylines = 0;
  for (std::size_t p = svg.find("<polyline"); p != std::string::npos; p = svg.find("<polyline", p + 1)) ++polylines;
  EXPECT_EQ(polylines, 2u);
  for (const char* text : {"ground truth", "estimate", "start", "end", "x [m]", "y [m]", " m</text>"}) {
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  }
  EXPECT_FALSE(TagsBalanced("<svg><g></svg></g>"));  // the checker itself can fail
}

}  // namespace
}  // namespace dammloam::eval

namespace dammloam::eval {
namespace {

std::vector<Eigen::Vector3d> GaussianFrames(std::size_t n, const Eigen::Vector3d& sigma,
                                            std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Vector3d> frames(n);
  for (Eigen::Vector3d& e : frames) {
    e = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).cwiseProduct(sigma);
  }
  return frames;
}

// Isotropic 3D Gaussian frame errors: the norm's median is 1.54 sigma and the largest of 850
// about 4.2 sigma, so the worst frame is ~2.7x the median from noise alone.
TEST(FrameTail, GaussianNoiseAloneSetsTheWorstFrameNearThreeMedians) {
  const FrameTail tail = AnalyseFrameTail(GaussianFrames(850, Eigen::Vector3d::Constant(0.005), 7));
  EXPECT_EQ(tail.frames, 850u);
  EXPECT_GT(tail.gaussian_median, 2.4);
  EXPECT_LT(tail.gaussian_median, 3.1);
  EXPECT_GT(tail.gaussian_p95, tail.gaussian_median);
  // The run is a draw of the same noise: inside the band, not flagged.
  EXPECT_LT(tail.worst_over_median, tail.gaussian_p95);
  EXPECT_GT(tail.gaussian_share_at_least, 0.05);
}

// One axis dominating (a wheeled robot's lateral shake) lowers the median frame more than the
// worst, and the noise alone passes 3x.
TEST(FrameTail, OneDominantAxisRaisesTheNoiseRatio) {
  const FrameTail isotropic =
      AnalyseFrameTail(GaussianFrames(1700, Eigen::Vector3d::Constant(0.005), 3));
  const FrameTail lateral =
      AnalyseFrameTail(GaussianFrames(1700, Eigen::Vector3d(0.001, 0.006, 0.001), 3));
  EXPECT_GT(lateral.gaussian_median, 3.0);
  EXPECT_GT(lateral.gaussian_median, isotropic.gaussian_median + 0.4);
}

TEST(FrameTail, ASingleWrongFrameStandsOutOfTheNoise) {
  std::vector<Eigen::Vector3d> frames = GaussianFrames(850, Eigen::Vector3d::Constant(0.005), 7);
  frames[400] = Eigen::Vector3d(0.0, 0.08, 0.0);  // 0.08 m against ~8 mm frames
  const FrameTail tail = AnalyseFrameTail(frames);
  EXPECT_GT(tail.worst_over_median, 2.0 * tail.gaussian_p95);
  EXPECT_EQ(tail.gaussian_share_at_least, 0.0);
}

TEST(FrameTail, TooFewOrMotionlessFramesAreNotJudged) {
  EXPECT_EQ(AnalyseFrameTail({Eigen::Vector3d(0.01, 0, 0), Eigen::Vector3d(0.02, 0, 0)}).frames, 0u);
  EXPECT_EQ(AnalyseFrameTail(std::vector<Eigen::Vector3d>(10, Eigen::Vector3d::Zero())).frames, 0u);
  // Error along one axis only: the covariance is singular, the analysis still runs.
  std::vector<Eigen::Vector3d> planar;
  for (int i = 0; i < 100; ++i) planar.emplace_back(0.001 * (i % 7) + 0.001, 0.0, 0.0);
  EXPECT_EQ(AnalyseFrameTail(planar).frames, 100u);
  EXPECT_GT(AnalyseFrameTail(planar).gaussian_median, 1.0);
}

TEST(FrameTail, EvaluateReportsItForTheRpe) {
  const auto gt = Helix();
  std::vector<StampedPose> est = gt;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 0.01);
  for (auto& pose : est) pose.T.translation() += Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  const TrajectoryMetrics m = EvaluateTrajectories(gt, est);
  EXPECT_EQ(m.rpe_tail.frames, m.rpe.count);
  EXPECT_NEAR(m.rpe_tail.worst_over_median, m.rpe.max / m.rpe.median, 1e-12);
  const nlohmann::json j = nlohmann::json::parse(FormatJson(m));
  EXPECT_NEAR(j["rpe_tail"]["worst_over_median"].get<double>(), m.rpe_tail.worst_over_median, 1e-12);
  EXPECT_NE(FormatTable(m).find("worst frame:"), std::string::npos);
}

}  // namespace
}  // namespace dammloam::eval
