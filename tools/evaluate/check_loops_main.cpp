// dammloam-check-loops GT.tum EVENTS.jsonl [--all] [--json]: which loops of a
// `dammloam-odometry --events` file are false against the ground truth.
#include <spdlog/fmt/fmt.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "io/io_error.hpp"
#include "io/tum.hpp"
#include "tools/evaluate/loop_truth.hpp"

namespace {

using namespace dammloam;

struct Counts {
  int accepted = 0, accepted_false = 0, refused = 0, refused_false = 0;
};

nlohmann::json ToJson(const eval::LoopVerdict& v) {
  const Eigen::Vector3d t = v.T_truth.translation();
  return {{"query_stamp", v.loop.query_stamp},      {"candidate_stamp", v.loop.candidate_stamp},
          {"accepted", v.loop.accepted},            {"reason", v.loop.reason},
          {"truth_translation", {t.x(), t.y(), t.z()}},
          {"translation_error_m", v.translation_error}, {"rotation_error_deg", v.rotation_error_deg},
          {"false", v.is_false}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Loop closures against the ground truth: a loop is false when its registered "
               "relative pose is more than --max-m metres or --max-deg degrees from the truth's"};
  std::string gt_file, events_file;
  bool all = false, json = false;
  eval::LoopLimits limits;
  app.add_option("gt", gt_file, "ground-truth trajectory (TUM), e.g. the sequence's gt.tum")->required();
  app.add_option("events", events_file, "loop events of dammloam-odometry --events (JSON lines)")->required();
  app.add_option("--max-m", limits.max_translation, "translation limit, metres")->capture_default_str();
  app.add_option("--max-deg", limits.max_rotation_deg, "rotation limit, degrees")->capture_default_str();
  app.add_option("--max-time-diff", limits.max_time_diff, "stamp matching tolerance, seconds")
      ->capture_default_str();
  app.add_flag("--all", all, "list refused candidates too (default: accepted loops only)");
  app.add_flag("--json", json, "one JSON object: counts and every listed loop");
  CLI11_PARSE(app, argc, argv);
  try {
    const std::vector<io::StampedPose> gt = io::ReadTum(gt_file);
    Counts counts;
    nlohmann::json listed = nlohmann::json::array();
    for (const eval::LoopToJudge& loop : eval::ReadLoopEvents(events_file)) {
      const eval::LoopVerdict v = eval::JudgeLoop(gt, loop, limits);
      (loop.accepted ? counts.accepted : counts.refused) += 1;
      if (v.is_false) (loop.accepted ? counts.accepted_false : counts.refused_false) += 1;
      if (!loop.accepted && !all) continue;
      if (json) {
        listed.push_back(ToJson(v));
        continue;
      }
      std::cout << fmt::format("{:.3f} -> {:.3f} {:8s} truth dz {:+6.2f} m  error {:6.3f} m {:6.2f} deg{}  {}\n",
                               loop.candidate_stamp, loop.query_stamp, loop.accepted ? "accepted" : "refused",
                               v.T_truth.translation().z(), v.translation_error, v.rotation_error_deg,
                               v.is_false ? "  FALSE" : "", loop.reason);
    }
    if (json) {
      std::cout << nlohmann::json{{"accepted", counts.accepted}, {"accepted_false", counts.accepted_false},
                                  {"refused", counts.refused}, {"refused_false", counts.refused_false},
                                  {"loops", listed}}.dump()
                << "\n";
    } else {
      std::cout << fmt::format("accepted {} (false {}), refused {} (false {})\n", counts.accepted,
                               counts.accepted_false, counts.refused, counts.refused_false);
    }
  } catch (const std::exception& e) {
    std::cerr << "dammloam-check-loops: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
