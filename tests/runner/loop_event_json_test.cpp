// The --events line format: every field present, values as in the event, one line.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tools/odometry/loop_event_json.hpp"

namespace dammloam::tools {
namespace {

TEST(LoopEventJson, CarriesIdsScoresAndDecision) {
  backend::LoopEvent e;
  e.query_keyframe = 42;
  e.candidate_keyframe = 3;
  e.query_scan_index = 420;
  e.candidate_scan_index = 30;
  e.query_stamp = 1700000042.05;
  e.candidate_stamp = 1700000003.0;
  e.scan_context_distance = 0.18;
  e.yaw_guess_rad = -0.5;
  e.inlier_ratio = 0.81;
  e.rmse = 0.04;
  e.T_candidate_query = Eigen::Translation3d(1.0, 2.0, 0.5) *
                        Eigen::AngleAxisd(0.25, Eigen::Vector3d::UnitZ());
  e.accepted = false;
  e.reason = "residual 0.14 m > 0.12 m";
  e.map_chi2 = 2.5;
  e.map_chi2_bound = 1.0;
  e.started_optimization = true;
  e.correction_m = 0.31;
  e.correction_rad = 0.02;
  e.solve_ms = 12.5;
  e.graph_nodes = 901;

  const std::string line = LoopEventJsonLine(e);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  const auto j = nlohmann::json::parse(line);
  EXPECT_EQ(j["query_keyframe"], 42);
  EXPECT_EQ(j["candidate_keyframe"], 3);
  EXPECT_EQ(j["query_scan_index"], 420);
  EXPECT_EQ(j["candidate_scan_index"], 30);
  EXPECT_DOUBLE_EQ(j["query_stamp"].get<double>(), 1700000042.05);
  EXPECT_DOUBLE_EQ(j["candidate_stamp"].get<double>(), 1700000003.0);
  EXPECT_DOUBLE_EQ(j["scan_context_distance"].get<double>(), 0.18);
  EXPECT_DOUBLE_EQ(j["yaw_guess_rad"].get<double>(), -0.5);
  EXPECT_DOUBLE_EQ(j["inlier_ratio"].get<double>(), 0.81);
  EXPECT_DOUBLE_EQ(j["rmse"].get<double>(), 0.04);
  EXPECT_FALSE(j["accepted"].get<bool>());
  EXPECT_EQ(j["reason"], "residual 0.14 m > 0.12 m");
  EXPECT_DOUBLE_EQ(j["map_chi2"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(j["map_chi2_bound"].get<double>(), 1.0);
  EXPECT_TRUE(j["started_optimization"].get<bool>());
  EXPECT_DOUBLE_EQ(j["correction_m"].get<double>(), 0.31);
  EXPECT_DOUBLE_EQ(j["correction_rad"].get<double>(), 0.02);
  EXPECT_DOUBLE_EQ(j["solve_ms"].get<double>(), 12.5);
  EXPECT_EQ(j["graph_nodes"], 901);
  const auto T = j["T_candidate_query"].get<std::vector<double>>();
  ASSERT_EQ(T.size(), 7u);
  EXPECT_DOUBLE_EQ(T[0], 1.0);
  EXPECT_DOUBLE_EQ(T[1], 2.0);
  EXPECT_DOUBLE_EQ(T[2], 0.5);
  EXPECT_NEAR(T[5], std::sin(0.125), 1e-12);  // qz of a 0.25 rad yaw
  EXPECT_NEAR(T[6], std::cos(0.125), 1e-12);  // qw
}

}  // namespace
}  // namespace dammloam::tools
