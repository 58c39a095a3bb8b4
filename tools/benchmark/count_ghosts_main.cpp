// dammloam-count-ghosts MAP_DIR --preset P --seed S [--sensor NAME] [--json]: how many points of a
// saved map (dammloam-odometry --save-map, dammloamd's save_map) lie where the simulator's
// actors were and have since left, against the union of the same keyframes without the
// vacated-point cleaning (issue 52's ghosts).
#include <spdlog/fmt/fmt.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/backend/global_map.hpp"
#include "io/mapstore/map_store.hpp"
#include "io/pcd/labelled_pcd.hpp"
#include "tools/benchmark/ghost_count.hpp"
#include "tools/evaluate/trajectory_metrics.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/sensor_spec.hpp"

namespace {

using namespace dammloam;

// Margin of the actors' bodies and how far their bottoms are raised off the ground they walked
// on (sim::SweptVolume): the ground is still there after they left.
constexpr double kSweepStep = 0.05, kBodyMargin = 0.05, kGroundClearance = 0.15;

struct Row {
  std::string name;
  bench::GhostCount count;
};

// T_truth_map from the keyframes' corrected positions against the simulator's at their stamps.
Eigen::Isometry3d AlignToTruth(const backend::MapData& map, const sim::Simulator& simulator) {
  std::vector<Eigen::Vector3d> est, truth;
  for (const backend::Keyframe& kf : map.keyframes) {
    est.push_back(kf.T_world_sensor.translation());
    truth.push_back(simulator.PoseAt(kf.stamp).translation());
  }
  if (est.size() < 3) throw std::runtime_error("the map has fewer than 3 keyframes: nothing to align");
  return eval::AlignUmeyama(est, truth);
}

bench::GhostCount Count(const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
                        const Eigen::Isometry3d& T_truth_map, const sim::SweptVolume& swept) {
  std::vector<Eigen::Vector3d> in_truth;
  in_truth.reserve(points.size());
  for (const Eigen::Vector3d& p : points) in_truth.push_back(T_truth_map * p);
  return bench::CountGhosts(in_truth, labels, swept);
}

nlohmann::json ToJson(const Row& row) {
  nlohmann::json by_class;
  for (std::size_t c = 0; c < kNumPointClasses; ++c) {
    by_class[std::string(Name(static_cast<PointClass>(c)))] = row.count.ghosts_by_class[c];
  }
  return {{"map", row.name},
          {"points", row.count.points},
          {"ghosts", row.count.ghosts},
          {"on_actors_at_end", row.count.on_actors},
          {"ghosts_by_class", by_class}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Ghosts in a saved map of a simulated run: points where actors were and have left"};
  std::string map_dir, preset_name, sensor_name = "vlp-16";
  std::uint64_t seed = 1;
  bool json = false;
  double global_voxel = 0.3;
  app.add_option("map", map_dir, "saved map directory")->required();
  app.add_option("--preset", preset_name, "the simulator preset the map was made on")
      ->required()
      ->check(CLI::IsMember(sim::PresetNames()));
  app.add_option("--seed", seed, "its seed")->capture_default_str();
  app.add_option("--sensor", sensor_name, "its sensor")->check(CLI::IsMember(sim::SensorNames()))
      ->capture_default_str();
  app.add_option("--global-voxel", global_voxel, "the back-end's global_map_voxel_size")->capture_default_str();
  std::string ghosts_out;
  app.add_option("--ghosts-out", ghosts_out, "write the saved map's ghosts (in its frame) as a labelled PCD");
  app.add_flag("--json", json, "one JSON object");
  CLI11_PARSE(app, argc, argv);
  try {
    const backend::MapData map = mapstore::LoadMap(map_dir);
    const sim::Simulator simulator(*sim::FindPreset(preset_name), *sim::MakeSensorSpec(sensor_name), seed);
    if (!simulator.has_actors()) throw std::runtime_error("preset " + preset_name + " has no actors");
    const Eigen::Isometry3d T_truth_map = AlignToTruth(map, simulator);
    const double t0 = simulator.options().t0;
    const double t_end = t0 + simulator.options().num_scans * simulator.sensor_model().scan_period;
    const sim::SweptVolume swept =
        simulator.ActorSweptVolume(t0, t_end, kSweepStep, kBodyMargin, kGroundClearance);
    // The keyframes as saved, without the cleaning (the moving points that stood in their views
    // are not saved, so the saved map's cleaning cannot be redone here).
    const backend::GlobalMap raw = backend::AssembleGlobalMap(map.keyframes, global_voxel);
    const std::vector<Row> rows = {{"saved", Count(map.global_points, map.global_labels, T_truth_map, swept)},
                                   {"keyframes", Count(raw.points, raw.labels, T_truth_map, swept)}};
    if (!ghosts_out.empty()) {
      io::LabelledCloud ghosts;
      for (std::size_t i : rows[0].count.ghost_indices) {
        ghosts.points.push_back(map.global_points[i]);
        if (map.global_labels.size() == map.global_points.size()) ghosts.labels.push_back(map.global_labels[i]);
      }
      io::WriteLabelledPcd(ghosts_out, ghosts, io::PcdEncoding::kAscii);
    }
    // What the cleaning took that was neither a ghost nor an actor: static scenery.
    const auto removed = static_cast<long long>(raw.points.size()) - static_cast<long long>(map.global_points.size());
    const long long static_removed =
        removed - (static_cast<long long>(rows[1].count.ghosts) - static_cast<long long>(rows[0].count.ghosts)) -
        (static_cast<long long>(rows[1].count.on_actors) - static_cast<long long>(rows[0].count.on_actors));
    if (json) {
      nlohmann::json out = {{"preset", preset_name}, {"seed", seed}, {"sensor", sensor_name},
                            {"keyframes", map.keyframes.size()}, {"removed", removed},
                            {"static_removed", static_removed}};
      for (const Row& row : rows) out["maps"].push_back(ToJson(row));
      std::cout << out.dump() << "\n";
      return 0;
    }
    for (const Row& row : rows) {
      std::cout << fmt::format("{:18s} points {:8d}  ghosts {:6d} ({:.3f} %)  on actors at the end {:5d}\n",
                               row.name, row.count.points, row.count.ghosts,
                               row.count.points > 0 ? 100.0 * row.count.ghosts / row.count.points : 0.0,
                               row.count.on_actors);
    }
    std::cout << fmt::format("the saved map has {} points fewer than its keyframes' union, {} of them static scenery\n",
                             removed, static_removed);
  } catch (const std::exception& e) {
    std::cerr << "dammloam-count-ghosts: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
