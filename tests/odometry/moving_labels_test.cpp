// The sixth class: points on things that move are labelled Moving in the odometry's output, the
// class counts follow, and the labels agree with the simulator's per-point truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "core/odometry/pipeline.hpp"
#include "tools/benchmark/moving_label_score.hpp"
#include "tools/benchmark/sim_run.hpp"
#include "tools/simulate/presets.hpp"

namespace dammloam {
namespace {

using bench::MovingLabelScore;
using bench::ScoreMovingLabels;
constexpr std::uint8_t kStatic = 0, kMoving = 1, kResting = 2;

TEST(MovingLabelScore, CountsEachKeptPointAgainstItsTruth) {
  // Input points 1 and 4 were dropped by the preprocessing; the result has the other four.
  const std::vector<std::uint8_t> truth = {kMoving, kStatic, kStatic, kMoving, kMoving, kResting};
  const std::vector<std::uint8_t> kept = {1, 0, 1, 1, 0, 1};
  const std::vector<PointClass> labels = {PointClass::Moving, PointClass::Moving, PointClass::Wall,
                                          PointClass::Moving};
  const MovingLabelScore s = ScoreMovingLabels(truth, kept, labels);
  EXPECT_EQ(s.moving_found, 1u);
  EXPECT_EQ(s.moving_missed, 1u);  // point 3 (point 4 was dropped: not scored)
  EXPECT_EQ(s.static_points, 1u);
  EXPECT_EQ(s.static_flagged, 1u);
  EXPECT_EQ(s.resting_points, 1u);
  EXPECT_EQ(s.resting_flagged, 1u);
  EXPECT_DOUBLE_EQ(s.Precision(), 0.5);  // the resting actor counts neither way
  EXPECT_DOUBLE_EQ(s.Recall(), 0.5);
  EXPECT_DOUBLE_EQ(s.StaticFlaggedShare(), 1.0);
  EXPECT_EQ(s.mismatched_scans, 0u);

  // A result whose size does not match the kept points is not scored, and says so.
  const MovingLabelScore bad = ScoreMovingLabels(truth, kept, {PointClass::Moving});
  EXPECT_EQ(bad.mismatched_scans, 1u);
  EXPECT_EQ(bad.moving_found + bad.moving_missed + bad.static_points, 0u);
}

// The wheeled zigzag among people (VLP-16, seed 1), moving points on.
class MovingClass : public ::testing::Test {
 protected:
  static constexpr int kScans = 150;  // the first 15 s
  static OdometryConfig MovingOn() {
    OdometryConfig config;
    config.moving.enabled = true;
    return config;
  }
};

TEST_F(MovingClass, MovingPointsAreLabelledMovingAndTheCountsFollow) {
  const auto preset = sim::FindPreset("wheeled-zigzag-people");
  ASSERT_TRUE(preset);
  const sim::Simulator simulator(*preset, sim::Vlp16(), /*seed=*/1);
  OdometryPipeline pipeline(MovingOn(), simulator.sensor_model());
  std::size_t moving_points = 0;
  for (int i = 0; i < 40; ++i) {
    const OdometryResult r = pipeline.Process(simulator.SimulateScan(i));
    ASSERT_TRUE(Registered(r.status)) << i;
    ASSERT_EQ(r.labels.size(), r.deskewed_points.size());
    ASSERT_TRUE(r.moving.empty() || r.moving.size() == r.labels.size());
    std::size_t labelled_moving = 0, total = 0;
    for (std::size_t k = 0; k < r.labels.size(); ++k) {
      EXPECT_EQ(r.labels[k] == PointClass::Moving, !r.moving.empty() && r.moving[k] != 0)
          << "scan " << i;
      labelled_moving += r.labels[k] == PointClass::Moving;
    }
    for (const std::uint32_t c : r.class_counts) total += c;
    EXPECT_EQ(total, r.labels.size()) << "scan " << i;
    EXPECT_EQ(r.class_counts[Index(PointClass::Moving)], labelled_moving) << "scan " << i;
    moving_points += labelled_moving;
  }
  // GCC release found a few thousand, clang ASan+UBSan 708 (floating-point differences move
  // the first detections): this checks that people are seen at all.
  EXPECT_GT(moving_points, 200u) << "people walk through the first 4 s";
}

TEST_F(MovingClass, LabelsAgreeWithTheSimulatorsTruth) {
  const auto preset = sim::FindPreset("wheeled-zigzag-people");
  ASSERT_TRUE(preset);
  const sim::Simulator simulator(*preset, sim::Vlp16(), /*seed=*/1);
  const bench::ScanStream stream = bench::SimulatedStream(simulator, kScans);
  ASSERT_TRUE(stream.labelled_scan) << "a preset with actors has per-point truth";
  const auto traces = bench::StreamModes(stream, {MovingOn(), OdometryConfig{}});
  const MovingLabelScore on = traces[0].MovingLabels();
  const MovingLabelScore off = traces[1].MovingLabels();
  std::printf("moving on: precision %.4f recall %.4f static labelled moving %.5f (%zu moving, "
              "%zu static points)\n",
              on.Precision(), on.Recall(), on.StaticFlaggedShare(),
              on.moving_found + on.moving_missed, on.static_points);
  EXPECT_EQ(on.mismatched_scans, 0u);
  ASSERT_GT(on.moving_found + on.moving_missed, 1000u) << "people are seen";
  // Measured (seed 1, 150 scans): precision 0.986, recall 0.838, static labelled moving
  // 0.019 %. Recall is short of the 90 %: people walking away from the sensor whose
  // trail is in the map, or who walk next to a wall, are missed (docs/measurements.md).
  EXPECT_GT(on.Precision(), 0.95);
  EXPECT_GT(on.Recall(), 0.80);
  EXPECT_LT(on.StaticFlaggedShare(), 0.005);
  // Off, nothing is labelled moving.
  EXPECT_EQ(off.moving_found + off.static_flagged + off.resting_flagged, 0u);
}

}  // namespace
}  // namespace dammloam
