// dammloam-simulate: writes a simulated sequence directory with exact ground truth.
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/sequence_io.hpp"
#include "tools/simulate/inertial_meta.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace {

using namespace dammloam;

struct Args {
  std::string scene, preset, sensor = "os1-64", out;
  std::optional<std::string> motion, range_model, firing_phase;
  std::optional<int> scans;
  std::optional<double> noise;
  sim::SimOptions sim;
  std::optional<int> rings, columns;
  std::optional<double> vfov_up, vfov_down, min_range, max_range;
  std::vector<double> vertical_angles;
  bool overwrite = false;
  sim::InertialStreamOptions streams;
};

// The named sensor with the command-line geometry overrides applied.
sim::SensorSpec MakeSpec(const Args& a) {
  sim::SensorSpec spec = *sim::MakeSensorSpec(a.sensor);  // name already checked by CLI11
  const bool geometry_changed = a.rings || a.columns || a.vfov_up || a.vfov_down ||
                                !a.vertical_angles.empty() || a.min_range || a.max_range;
  if (!a.vertical_angles.empty()) {
    if (a.vfov_up || a.vfov_down) {
      throw std::invalid_argument("--vertical-angles cannot be combined with --vfov-up/--vfov-down");
    }
    if (a.rings && *a.rings != static_cast<int>(a.vertical_angles.size())) {
      throw std::invalid_argument("--rings " + std::to_string(*a.rings) + " but --vertical-angles has " +
                                  std::to_string(a.vertical_angles.size()) + " values");
    }
    spec.vertical_angles_deg = a.vertical_angles;
  } else if (a.rings || a.vfov_up || a.vfov_down) {
    spec.vertical_angles_deg = sim::UniformVerticalAngles(
        a.rings.value_or(spec.rings()), a.vfov_up.value_or(spec.vertical_angles_deg.front()),
        a.vfov_down.value_or(spec.vertical_angles_deg.back()));
  }
  if (a.columns) spec.columns = *a.columns;
  if (a.min_range) spec.min_range = *a.min_range;
  if (a.max_range) spec.max_range = *a.max_range;
  if (geometry_changed) spec.name = "custom-" + spec.name;
  if (const std::string why = sim::Validate(spec); !why.empty()) {
    throw std::invalid_argument("sensor geometry: " + why);
  }
  return spec;
}

// labels/NNNNNN.bin beside scans/: one uint8 per point of the scan file, in its order (see
// docs/presets.md). Kept out of the shared sequence format: readers that do not know it skip it.
class LabelWriter {
 public:
  // Clears labels a previous run left in `dir` (only reached once the sequence writer accepted
  // the directory), then creates the folder if this run has actors.
  LabelWriter(const std::filesystem::path& dir, bool enabled) : dir_(dir / "labels"), enabled_(enabled) {
    std::filesystem::remove_all(dir_);
    if (enabled_) std::filesystem::create_directories(dir_);
  }
  void Write(std::size_t index, const std::vector<std::uint8_t>& labels) const {
    if (!enabled_) return;
    const std::filesystem::path file = dir_ / io::ScanFileName(index);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(labels.data()), static_cast<std::streamsize>(labels.size()));
    if (!out) throw io::IoError(file.string() + ": cannot write labels");
  }

 private:
  std::filesystem::path dir_;
  bool enabled_;
};

std::string ActorSummary(const sim::ActorSet& actors) {
  if (actors.empty()) return "none";
  return fmt::format("{} pedestrians ({} keeping pace, {} leading), {} vehicles ({} parking, {} leaving), {} doors",
                     actors.Count(sim::ActorKind::Pedestrian), actors.Count(sim::ActorRole::Companion),
                     actors.Count(sim::ActorRole::Leader), actors.Count(sim::ActorKind::Vehicle),
                     actors.Count(sim::ActorRole::Parking), actors.Count(sim::ActorRole::Leaving),
                     actors.Count(sim::ActorKind::Door));
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

int Run(const Args& a) {
  const sim::SensorSpec spec = MakeSpec(a);
  sim::SimOptions options = a.sim;
  sim::SceneKind scene = sim::SceneKind::Corridor;
  int scans = 0;
  if (!a.preset.empty()) {
    const sim::Preset preset = *sim::FindPreset(a.preset);  // name already checked by CLI11
    const sim::SimOptions planned = preset.Options(options.seed);
    scene = preset.scene;
    options.motion = planned.motion;
    options.num_scans = planned.num_scans;
    options.noise_sigma = planned.noise_sigma;
    options.full_range_reflectivity = planned.full_range_reflectivity;
    options.actors = planned.actors;
    options.handheld_profile = planned.handheld_profile;
    // Was missing until 2026-11-29: the CLI's handheld-look-around walked without its swings
    // (the library, and so the benchmark, had them).
    options.look_arounds_per_minute = planned.look_arounds_per_minute;
    scans = a.scans.value_or(preset.scans);
  } else {
    if (a.scene.empty()) throw std::invalid_argument("--scene or --preset is required");
    if (!a.scans) throw std::invalid_argument("--scans is required with --scene");
    scene = *sim::ParseSceneKind(a.scene);
    options.motion = *sim::ParseMotionKind(a.motion.value_or("constant"));
    options.num_scans = *a.scans;
    options.noise_sigma = sim::DefaultNoise(options.motion);
    options.full_range_reflectivity = sim::DefaultFullRangeReflectivity(options.motion);
    scans = *a.scans;
  }
  if (a.noise) options.noise_sigma = *a.noise;
  if (a.firing_phase) {
    options.firing_phase =
        *a.firing_phase == "random" ? sim::kRandomFiringPhase : std::stod(*a.firing_phase);
  }
  if (a.range_model) {
    options.full_range_reflectivity =
        *a.range_model == "realistic" ? sim::kRealisticFullRangeReflectivity : 0.0;
  }
  std::unique_ptr<tbb::global_control> limit;
  if (options.threads > 1) {
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<std::size_t>(options.threads));
  }
  const auto setup_start = std::chrono::steady_clock::now();
  const sim::Simulator simulator(scene, spec, options);
  const double setup_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - setup_start).count();

  io::SequenceMeta meta{spec.name, simulator.sensor_model(), io::PointLayout::kXYZITR};
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, scans, a.streams);
  sim::DescribeStreams(streams, &meta);
  io::SequenceWriter writer(a.out, meta, a.overwrite);
  if (streams.imu) writer.WriteImu(*streams.imu);
  if (streams.wheel) writer.WriteWheel(*streams.wheel);
  const LabelWriter label_writer(a.out, simulator.has_actors());
  std::vector<std::uint8_t> labels;
  std::vector<io::StampedPose> ground_truth;
  std::vector<double> sim_ms;
  std::vector<double> points;
  const auto run_start = std::chrono::steady_clock::now();
  for (int i = 0; i < scans; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const Scan scan = simulator.SimulateScan(i, simulator.has_actors() ? &labels : nullptr);
    sim_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    points.push_back(static_cast<double>(scan.size()));
    label_writer.Write(writer.size(), labels);
    writer.Write(scan);
    ground_truth.push_back({scan.t_start, simulator.PoseAt(scan.t_start)});
  }
  writer.WriteGroundTruth(ground_truth);

  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();

  // Speed over the run from the ground truth, scan to scan (what a motion model has to follow).
  std::vector<double> speeds;
  double path_length = 0.0;
  for (std::size_t k = 1; k < ground_truth.size(); ++k) {
    const double d = (ground_truth[k].T.translation() - ground_truth[k - 1].T.translation()).norm();
    path_length += d;
    speeds.push_back(d / (ground_truth[k].t - ground_truth[k - 1].t));
  }
  const auto [slowest, fastest] = speeds.empty() ? std::pair{0.0, 0.0}
                                                 : std::pair{*std::min_element(speeds.begin(), speeds.end()),
                                                             *std::max_element(speeds.begin(), speeds.end())};
  const Eigen::Vector3d travelled = ground_truth.back().T.translation() - ground_truth.front().T.translation();
  const std::string speed =
      options.motion != sim::MotionKind::Constant
          ? std::string(sim::MotionName(options.motion))
          : fmt::format("{}", options.speed > 0 ? options.speed : sim::DefaultSpeed(simulator.kind()));
  spdlog::info(
      "simulate: scene={}{} sensor={} ({}x{}) scans={} seed={} noise={} m speed={} m/s "
      "recess depth={} m firing phase={} threads={} "
      "range={} points/scan median={:.0f} sim median {:.2f} ms/scan, start-end distance {:.2f} m -> {}",
      sim::SceneName(scene), a.preset.empty() ? "" : " preset=" + a.preset, spec.name, spec.rings(),
      spec.columns, scans, options.seed, options.noise_sigma, speed, options.recess_depth,
      options.firing_phase == sim::kRandomFiringPhase ? std::string("random")
                                                      : fmt::format("{}", options.firing_phase),
      options.threads == 0 ? std::string("auto") : std::to_string(options.threads),
      options.full_range_reflectivity > 0 ? "realistic" : "ideal", Median(points), Median(sim_ms),
      travelled.norm(), a.out);
  spdlog::info(
      "simulate: path {:.1f} m in {:.1f} s, speed min/median/max {:.2f}/{:.2f}/{:.2f} m/s; setup "
      "{:.0f} ms, {} scans simulated and written in {:.1f} s",
      path_length, ground_truth.back().t - ground_truth.front().t, slowest, Median(speeds), fastest,
      setup_ms, scans, total_s);
  spdlog::info("simulate: {}", sim::StreamsSummary(streams));
  spdlog::info("simulate: actors: {}{}", ActorSummary(simulator.actors()),
               simulator.has_actors() ? " (point labels in labels/)" : "");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Simulate a spinning LiDAR in an analytic scene and write a sequence directory"};
  Args a;
  std::string scenes, motions, presets;
  for (const auto& n : sim::SceneNames()) scenes += (scenes.empty() ? "" : ", ") + n;
  for (const auto& n : sim::MotionNames()) motions += (motions.empty() ? "" : ", ") + n;
  for (const sim::Preset& p : sim::Presets()) {
    presets += fmt::format("\n  {:<18} {} + {}, {} scans: {}", p.name, sim::SceneName(p.scene),
                           sim::MotionName(p.motion), p.scans, p.what);
  }
  app.footer("Scenes: " + scenes + "\nMotions: " + motions + "\nPresets (--preset NAME):" + presets);
  auto* scene = app.add_option("--scene", a.scene, "Scene")->check(CLI::IsMember(sim::SceneNames()));
  auto* motion = app.add_option("--motion", a.motion,
                                "Carrier: constant (default; speed ramp then constant), handheld, "
                                "legged, wheeled, vehicle (seeded by --seed)")
                     ->check(CLI::IsMember(sim::MotionNames()));
  app.add_option("--preset", a.preset, "Realistic preset: scene, motion, noise, range model, scans")
      ->check(CLI::IsMember(sim::PresetNames()))
      ->excludes(scene)
      ->excludes(motion);
  app.add_option("--sensor", a.sensor, "Sensor model")->check(CLI::IsMember(sim::SensorNames()))
      ->capture_default_str();
  app.add_option("--scans", a.scans, "Number of scans (required with --scene; a preset's default: "
                                     "its whole walk)")
      ->check(CLI::PositiveNumber);
  app.add_option("--out", a.out, "Output sequence directory")->required();
  app.add_flag("--overwrite", a.overwrite, "Replace an existing sequence in --out");
  app.add_option("--seed", a.sim.seed, "Seed of the range noise and the motion")->capture_default_str();
  app.add_option("--noise", a.noise,
                 "Range noise sigma, metres (default 0.01 for constant motion, 0.015 otherwise)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--range-model", a.range_model,
                 "ideal: every hit up to max range (default for constant motion); realistic: dark "
                 "or grazing surfaces fade earlier (default otherwise)")
      ->check(CLI::IsMember({"ideal", "realistic"}));
  app.add_option("--recess-depth", a.sim.recess_depth,
                 "Depth of the door recesses of long-, endless- and straight-corridor, metres "
                 "(the presets' 0.05: plain office doors)")
      ->check(CLI::Range(0.001, sim::kMaxRecessDepth))
      ->capture_default_str();
  app.add_option("--firing-phase", a.firing_phase,
                 "Where columns fire within a turn, in columns: 0 (default) exactly at k / "
                 "columns, on the range image's column boundaries; a number in [0, 1): that "
                 "offset; random: a fresh offset per scan (a free-running motor, as real sensors)")
      ->check([](const std::string& v) -> std::string {
        if (v == "random") return {};
        try {
          std::size_t used = 0;
          const double x = std::stod(v, &used);
          if (used == v.size() && x >= 0.0 && x < 1.0) return {};
        } catch (const std::exception&) {
        }
        return "expected 'random' or a number in [0, 1), got '" + v + "'";
      });
  app.add_option("--dropout", a.sim.dropout, "Probability that a return is lost")
      ->check(CLI::Range(0.0, 0.99))->capture_default_str();
  app.add_option("--speed", a.sim.speed,
                 "Speed in m/s (default: the scene's; other motions: the middle of their range)")
      ->check(CLI::PositiveNumber);
  app.add_option("--t0", a.sim.t0, "Start time of scan 0, seconds")->capture_default_str();
  app.add_option("--threads", a.sim.threads, "Threads (0: all cores, 1: single-threaded)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_flag("--no-imu", a.streams.no_imu, "Do not write imu.csv (written by default)");
  app.add_flag("--no-wheel", a.streams.no_wheel,
               "Do not write wheel.csv (written by default for the wheeled and vehicle carriers)");
  app.add_option("--imu-rate", a.streams.imu.rate_hz, "IMU rate, Hz (the OS1's: 100)")
      ->check(CLI::Range(1.0, 2000.0))->capture_default_str();
  app.add_option("--imu-time-offset", a.streams.imu.description.time_offset,
                 "IMU stamp minus the LiDAR-clock time of its measurement, seconds")
      ->check(CLI::Range(-0.5, 0.5))->capture_default_str();
  app.add_option("--wheel-rate", a.streams.wheel.rate_hz, "Wheel odometry rate, Hz")
      ->check(CLI::Range(1.0, 2000.0))->capture_default_str();
  app.add_option("--rings", a.rings, "Override: number of rings")->check(CLI::Range(1, 256));
  app.add_option("--columns", a.columns, "Override: columns per revolution")->check(CLI::Range(1, 16384));
  app.add_option("--vfov-up", a.vfov_up, "Override: elevation of the top ring, degrees");
  app.add_option("--vfov-down", a.vfov_down, "Override: elevation of the bottom ring, degrees");
  app.add_option("--vertical-angles", a.vertical_angles,
                 "Override: ring elevations in degrees, top ring first (comma separated)")
      ->delimiter(',');
  app.add_option("--min-range", a.min_range, "Override: minimum range, metres");
  app.add_option("--max-range", a.max_range, "Override: maximum range, metres");
  CLI11_PARSE(app, argc, argv);

  try {
    return Run(a);
  } catch (const std::exception& e) {
    spdlog::error("dammloam-simulate: {}", e.what());
    return 1;
  }
}
