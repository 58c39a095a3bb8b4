#include "tools/evaluate/loop_truth.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "io/io_error.hpp"

namespace dammloam::eval {

namespace {

const io::StampedPose& PoseAt(const std::vector<io::StampedPose>& gt, double t, double max_time_diff) {
  const auto later = std::lower_bound(gt.begin(), gt.end(), t,
                                      [](const io::StampedPose& p, double v) { return p.t < v; });
  auto best = gt.end();
  if (later != gt.end()) best = later;
  if (later != gt.begin() && (best == gt.end() || t - std::prev(later)->t < best->t - t)) best = std::prev(later);
  if (best == gt.end() || std::abs(best->t - t) > max_time_diff) {
    throw std::invalid_argument("no ground-truth pose within " + std::to_string(max_time_diff) +
                                " s of stamp " + std::to_string(t));
  }
  return *best;
}

}  // namespace

std::vector<LoopToJudge> ReadLoopEvents(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw io::IoError(file + ": cannot open");
  std::vector<LoopToJudge> loops;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      const nlohmann::json j = nlohmann::json::parse(line);
      const std::vector<double> pose = j.at("T_candidate_query").get<std::vector<double>>();
      if (pose.size() != 7) throw std::invalid_argument("T_candidate_query needs 7 values");
      LoopToJudge loop;
      loop.query_stamp = j.at("query_stamp").get<double>();
      loop.candidate_stamp = j.at("candidate_stamp").get<double>();
      loop.T_candidate_query.translation() = Eigen::Vector3d(pose[0], pose[1], pose[2]);
      loop.T_candidate_query.linear() =
          Eigen::Quaterniond(pose[6], pose[3], pose[4], pose[5]).normalized().toRotationMatrix();
      loop.accepted = j.at("accepted").get<bool>();
      loop.reason = j.value("reason", std::string());
      loops.push_back(loop);
    } catch (const std::exception& e) {
      throw io::IoError(file + ":" + std::to_string(number) + ": " + e.what());
    }
  }
  return loops;
}

LoopVerdict JudgeLoop(const std::vector<io::StampedPose>& gt, const LoopToJudge& loop, const LoopLimits& limits) {
  LoopVerdict v;
  v.loop = loop;
  const Eigen::Isometry3d& candidate = PoseAt(gt, loop.candidate_stamp, limits.max_time_diff).T;
  const Eigen::Isometry3d& query = PoseAt(gt, loop.query_stamp, limits.max_time_diff).T;
  v.T_truth = candidate.inverse() * query;
  const Eigen::Isometry3d error = v.T_truth.inverse() * loop.T_candidate_query;
  v.translation_error = error.translation().norm();
  v.rotation_error_deg = Eigen::AngleAxisd(error.rotation()).angle() * 180.0 / M_PI;
  v.is_false = v.translation_error > limits.max_translation || v.rotation_error_deg > limits.max_rotation_deg;
  return v;
}

}  // namespace dammloam::eval
