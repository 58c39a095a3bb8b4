// Loop events judged against the ground truth (tools/evaluate/loop_truth.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tools/evaluate/loop_truth.hpp"

namespace dammloam::eval {
namespace {

// Two places 3 m apart vertically (two floors), the second turned 90 deg.
std::vector<io::StampedPose> TwoPlaces() {
  io::StampedPose a, b;
  a.t = 100.0;
  a.T.translation() = Eigen::Vector3d(1.0, 2.0, 1.4);
  b.t = 200.0;
  b.T.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  b.T.translation() = Eigen::Vector3d(1.5, 2.0, 4.4);
  return {a, b};
}

LoopToJudge LoopFromTruth(const std::vector<io::StampedPose>& gt) {
  LoopToJudge loop;
  loop.candidate_stamp = gt[0].t;
  loop.query_stamp = gt[1].t;
  loop.T_candidate_query = gt[0].T.inverse() * gt[1].T;
  loop.accepted = true;
  return loop;
}

TEST(LoopTruth, TheTruthsOwnRelativePoseIsTrue) {
  const auto gt = TwoPlaces();
  const LoopVerdict v = JudgeLoop(gt, LoopFromTruth(gt), {});
  EXPECT_NEAR(v.translation_error, 0.0, 1e-9);
  EXPECT_NEAR(v.rotation_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(v.T_truth.translation().z(), 3.0, 1e-9);
  EXPECT_FALSE(v.is_false);
}

TEST(LoopTruth, ALoopOntoTheFloorBelowOrTurnedTooFarIsFalse) {
  const auto gt = TwoPlaces();
  LoopToJudge same_floor = LoopFromTruth(gt);
  same_floor.T_candidate_query.translation().z() -= 3.0;  // "the same place": off by a storey
  EXPECT_TRUE(JudgeLoop(gt, same_floor, {}).is_false);
  LoopToJudge turned = LoopFromTruth(gt);
  turned.T_candidate_query.linear() =
      turned.T_candidate_query.linear() * Eigen::AngleAxisd(6.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const LoopVerdict v = JudgeLoop(gt, turned, {});
  EXPECT_NEAR(v.rotation_error_deg, 6.0, 1e-6);
  EXPECT_TRUE(v.is_false);
  LoopToJudge close = LoopFromTruth(gt);
  close.T_candidate_query.translation().x() += 0.9;
  EXPECT_FALSE(JudgeLoop(gt, close, {}).is_false);
}

TEST(LoopTruth, AStampWithoutGroundTruthIsAnError) {
  const auto gt = TwoPlaces();
  LoopToJudge loop = LoopFromTruth(gt);
  loop.query_stamp = 150.0;
  EXPECT_THROW(JudgeLoop(gt, loop, {}), std::invalid_argument);
}

TEST(LoopTruth, ReadsTheOdometryToolsEventLines) {
  const test::TempDir dir;
  test::WriteText(dir / "events.jsonl",
                  "{\"query_stamp\": 200.0, \"candidate_stamp\": 100.0, \"accepted\": true, "
                  "\"reason\": \"accepted\", \"T_candidate_query\": [1, 2, 3, 0, 0, 0, 1]}\n\n"
                  "{\"query_stamp\": 300.0, \"candidate_stamp\": 100.0, \"accepted\": false, "
                  "\"T_candidate_query\": [0, 0, 0, 0, 0, 0.7071068, 0.7071068]}\n");
  const std::vector<LoopToJudge> loops = ReadLoopEvents((dir / "events.jsonl").string());
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_TRUE(loops[0].accepted);
  EXPECT_EQ(loops[0].reason, "accepted");
  EXPECT_NEAR(loops[0].T_candidate_query.translation().y(), 2.0, 1e-12);
  EXPECT_FALSE(loops[1].accepted);
  EXPECT_NEAR(Eigen::AngleAxisd(loops[1].T_candidate_query.rotation()).angle(), M_PI / 2, 1e-6);
  test::WriteText(dir / "bad.jsonl", "{\"query_stamp\": 1}\n");
  EXPECT_THROW(ReadLoopEvents((dir / "bad.jsonl").string()), std::exception);
}

}  // namespace
}  // namespace dammloam::eval
