#include "tools/simulate/simulator.hpp"

#include "tools/simulate/presets.hpp"
#include "tools/simulate/random_stream.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace dammloam::sim {

namespace {

// One SplitMix64 stream per (seed, scan, column) makes the noise independent of how columns
// are spread over threads.
SplitMix64 ColumnStream(std::uint64_t seed, int scan, int column) {
  SplitMix64 mix{seed};
  mix.state = mix.Next() ^ static_cast<std::uint64_t>(scan) * 0xD1B54A32D192ED03ull;
  mix.state = mix.Next() ^ static_cast<std::uint64_t>(column) * 0x8CB92BA72F3D8DD7ull;
  return mix;
}

// Firing time of a column since the scan start, rounded to float exactly as Scan stores it.
float ColumnTime(const SensorSpec& s, int column) {
  return static_cast<float>(s.scan_period * column / s.columns);
}

}  // namespace

Simulator::Simulator(SceneKind kind, SensorSpec sensor, SimOptions options)
    : kind_(kind),
      sensor_(std::move(sensor)),
      options_(options),
      world_(MakeWorld(kind, sensor_, options)),
      trajectory_(world_.motion) {
  if (const std::string why = Validate(sensor_); !why.empty()) {
    throw std::invalid_argument("sensor '" + sensor_.name + "': " + why);
  }
  if (!(options_.noise_sigma >= 0.0)) throw std::invalid_argument("noise sigma must be >= 0");
  if (!(options_.dropout >= 0.0 && options_.dropout < 1.0)) {
    throw std::invalid_argument("dropout probability must be in [0, 1)");
  }
  if (!(options_.firing_phase == kRandomFiringPhase ||
        (options_.firing_phase >= 0.0 && options_.firing_phase < 1.0))) {
    throw std::invalid_argument("firing phase must be in [0, 1) columns or random, got " +
                                std::to_string(options_.firing_phase));
  }
  if (options_.actors.any()) {
    const double duration = std::max(options_.num_scans, 1) * sensor_.scan_period;
    actors_ = PlaceActors(options_.actors, world_, trajectory_, duration, options_.seed);
  }
  const int rings = sensor_.rings();
  beam_dirs_.resize(static_cast<std::size_t>(sensor_.columns) * rings);
  for (int c = 0; c < sensor_.columns; ++c) {
    const double az = ColumnAzimuth(sensor_, c);
    for (int r = 0; r < rings; ++r) {
      const double el = sensor_.vertical_angles_deg[static_cast<std::size_t>(r)] * std::numbers::pi / 180.0;
      beam_dirs_[static_cast<std::size_t>(c) * rings + r] =
          Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    }
  }
}

Simulator::Simulator(const Preset& preset, SensorSpec sensor, std::uint64_t seed, int threads)
    : Simulator(preset.scene, std::move(sensor), [&] {
        SimOptions options = preset.Options(seed);
        options.threads = threads;
        return options;
      }()) {}

std::vector<std::string> Simulator::SceneNames() { return sim::SceneNames(); }

World Simulator::MakeWorld(SceneKind kind, const SensorSpec& sensor, const SimOptions& options) {
  // Checked before the scene is built from it: a recess needs jambs.
  if (!(options.recess_depth > 0.0 && options.recess_depth <= kMaxRecessDepth)) {
    throw std::invalid_argument("recess depth must be in (0, " + std::to_string(kMaxRecessDepth) +
                                "] m, got " + std::to_string(options.recess_depth));
  }
  const double duration = std::max(options.num_scans, 1) * sensor.scan_period;
  if (options.motion == MotionKind::Constant) {
    return BuildWorld(kind, options.speed, duration, options.recess_depth);
  }
  MotionSpec carrier;
  carrier.kind = options.motion;
  if (options.handheld_profile) carrier.handheld = *options.handheld_profile;
  const CarrierParams params = CarrierParamsOf(carrier);
  // --speed rescales the carrier's speeds so that the middle of its range is `speed`.
  const double scale = options.speed > 0.0 ? 2.0 * options.speed / (params.speed_min + params.speed_max) : 1.0;
  // Corridor scenes are sized for the fastest walk; a slower one stops at the path's end.
  World w = BuildWorld(kind, scale * params.speed_max, duration, options.recess_depth);
  w.motion.kind = options.motion;
  w.motion.seed = options.seed;
  w.motion.duration = duration;
  w.motion.sensor_height = params.sensor_height;
  auto rescale = [scale](auto& profile) {
    profile.speed_min *= scale;
    profile.speed_max *= scale;
  };
  if (options.handheld_profile) {
    w.motion.handheld = *options.handheld_profile;
  } else {
    w.motion.handheld.look_arounds_per_minute = options.look_arounds_per_minute;
  }
  rescale(w.motion.handheld);
  rescale(w.motion.legged);
  rescale(w.motion.wheeled);
  rescale(w.motion.vehicle);
  return w;
}

double Simulator::ScanStartTime(int index) const {
  return options_.t0 + index * sensor_.scan_period;
}

Eigen::Isometry3d Simulator::PoseAt(double t) const { return trajectory_.Pose(t - options_.t0); }

double Simulator::FiringPhase(int index) const {
  if (options_.firing_phase != kRandomFiringPhase) return options_.firing_phase;
  // Its own stream (column -1), so the noise of every beam stays what it was.
  return ColumnStream(options_.seed, index, -1).Uniform();
}

std::vector<ActorFootprint> Simulator::ActorFootprintsAt(double t) const {
  return actors_.FootprintsAt(t - options_.t0);
}

SweptVolume Simulator::ActorSweptVolume(double t_from, double t_to) const {
  return SweptVolume(actors_, t_from - options_.t0, t_to - options_.t0);
}

SweptVolume Simulator::ActorSweptVolume(double t_from, double t_to, double step, double margin,
                                        double clearance) const {
  return SweptVolume(actors_, t_from - options_.t0, t_to - options_.t0, step, margin, clearance);
}

std::vector<PosedPart> Simulator::ActorsInColumn(int column, double t, const Eigen::Isometry3d& T_world_sensor,
                                                 const std::optional<Eigen::Matrix3d>& R_phase,
                                                 const std::vector<ActorSet::Reach>& reach) const {
  std::vector<PosedPart> parts;
  if (reach.empty()) return parts;
  // The column's beams span the vertical half-plane at its azimuth (turned by the phase).
  const double az = ColumnAzimuth(sensor_, column);
  Eigen::Vector3d forward(std::cos(az), std::sin(az), 0.0), normal(-std::sin(az), std::cos(az), 0.0);
  if (R_phase) {
    forward = *R_phase * forward;
    normal = *R_phase * normal;
  }
  actors_.PoseForColumn(reach, t - options_.t0, T_world_sensor.translation(), T_world_sensor.linear() * forward,
                        T_world_sensor.linear() * normal, sensor_.max_range, &parts);
  return parts;
}

void Simulator::SimulateColumn(int index, int column, double t_start,
                               const std::optional<Eigen::Matrix3d>& R_phase,
                               const std::vector<ActorSet::Reach>& reach, Return* out) const {
  const double t = t_start + ColumnTime(sensor_, column);
  const Eigen::Isometry3d T_world_sensor = PoseAt(t);
  const std::vector<PosedPart> actors = ActorsInColumn(column, t, T_world_sensor, R_phase, reach);
  SplitMix64 rng = ColumnStream(options_.seed, index, column);
  const int rings = sensor_.rings();
  for (int r = 0; r < rings; ++r) {
    // Draw both numbers for every beam so one beam's fate never shifts another's noise.
    const double noise = options_.noise_sigma * rng.Gaussian();
    const bool dropped = rng.Uniform() < options_.dropout;
    const Eigen::Vector3d& column_dir = beam_dirs_[static_cast<std::size_t>(column) * rings + r];
    const Eigen::Vector3d dir = R_phase ? Eigen::Vector3d(*R_phase * column_dir) : column_dir;
    const Ray ray{T_world_sensor.translation(), T_world_sensor.linear() * dir};
    std::optional<Hit> hit = world_.scene.Cast(ray, 1e-6, sensor_.max_range);
    PointLabel label = PointLabel::Static;
    if (!actors.empty()) {
      Hit nearest = hit.value_or(Hit{sensor_.max_range, Eigen::Vector3d::UnitZ(), 0.0f});
      label = ActorSet::Intersect(actors, ray, 1e-6, nearest);
      if (label != PointLabel::Static) hit = nearest;
    }
    if (!hit || dropped || hit->t < sensor_.min_range) continue;
    if (options_.full_range_reflectivity > 0.0) {
      // Lambertian return power ~ reflectivity * cos(incidence) / r^2 against a fixed threshold.
      const double signal = hit->reflectivity * std::abs(hit->normal.dot(ray.dir)) /
                            options_.full_range_reflectivity;
      if (hit->t > sensor_.max_range * std::sqrt(signal)) continue;
    }
    const double range = hit->t + noise;
    if (range < sensor_.min_range || range > sensor_.max_range) continue;
    // Return strength: material reflectivity times incidence (Lambertian-like), 0..255.
    const double incidence = std::abs(hit->normal.dot(ray.dir));
    out[r] = {range * dir, static_cast<float>(255.0 * hit->reflectivity * (0.2 + 0.8 * incidence)),
              true, label};
  }
}

Scan Simulator::SimulateScan(int index, std::vector<std::uint8_t>* actor_labels) const {
  const int rings = sensor_.rings(), columns = sensor_.columns;
  Scan scan;
  scan.t_start = ScanStartTime(index);
  std::vector<Return> returns(static_cast<std::size_t>(columns) * rings);
  const double phase = FiringPhase(index);
  // The sensor turns clockwise (azimuth falls with the column): a later phase is a smaller angle.
  std::optional<Eigen::Matrix3d> R_phase;
  if (phase != 0.0) {
    R_phase = Eigen::AngleAxisd(-2.0 * std::numbers::pi * phase / columns, Eigen::Vector3d::UnitZ())
                  .toRotationMatrix();
  }
  // Every actor that may come into view during the scan, once, instead of once per column.
  const double drive_start = scan.t_start - options_.t0;
  const std::vector<ActorSet::Reach> reach =
      actors_.empty() ? std::vector<ActorSet::Reach>{}
                      : actors_.ReachDuring(drive_start, drive_start + sensor_.scan_period);
  auto run = [&](int c0, int c1) {
    for (int c = c0; c < c1; ++c) {
      SimulateColumn(index, c, scan.t_start, R_phase, reach, &returns[static_cast<std::size_t>(c) * rings]);
    }
  };
  if (options_.threads == 1) {
    run(0, columns);
  } else {
    tbb::parallel_for(tbb::blocked_range<int>(0, columns, 16),
                      [&](const tbb::blocked_range<int>& r) { run(r.begin(), r.end()); });
  }
  std::size_t valid = 0;
  for (const Return& ret : returns) valid += ret.valid ? 1 : 0;
  scan.points.reserve(valid);
  scan.intensities.reserve(valid);
  scan.times.reserve(valid);
  scan.rings.reserve(valid);
  if (actor_labels) {
    actor_labels->clear();
    actor_labels->reserve(valid);
  }
  for (int c = 0; c < columns; ++c) {
    for (int r = 0; r < rings; ++r) {
      const Return& ret = returns[static_cast<std::size_t>(c) * rings + r];
      if (!ret.valid) continue;
      scan.points.push_back(ret.point);
      scan.intensities.push_back(ret.intensity);
      scan.times.push_back(ColumnTime(sensor_, c));
      scan.rings.push_back(static_cast<std::int16_t>(r));
      if (actor_labels) actor_labels->push_back(static_cast<std::uint8_t>(ret.label));
    }
  }
  return scan;
}

}  // namespace dammloam::sim
