#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/scan.hpp"
#include "tools/simulate/actor_layouts.hpp"
#include "tools/simulate/actors.hpp"
#include "tools/simulate/scenes.hpp"
#include "tools/simulate/sensor_spec.hpp"
#include "tools/simulate/swept_volume.hpp"

namespace dammloam::sim {

struct Preset;  // presets.hpp

struct SimOptions {
  std::uint64_t seed = 1;     // range noise and (a separate stream) the carrier's motion
  double noise_sigma = 0.01;  // Gaussian range noise, metres (presets and the CLI use 0.015
                              // for the non-constant carriers)
  double dropout = 0.0;       // probability that a return is lost
  double speed = 0.0;         // m/s along the path; <= 0: the scene's default (constant) or
                              // the carrier's own speeds (others: > 0 rescales their middle)
  int num_scans = 600;        // the planned run: sizes corridor scenes so the whole drive stays
                              // inside, and plans a carrier's walk (fixed-size scenes end it
                              // 2 s before); simulating fewer scans gives a prefix of the run
  double t0 = 1700000000.0;   // start time of scan 0, seconds
  int threads = 0;            // 1: plain loop; otherwise a TBB parallel_for over columns
  MotionKind motion = MotionKind::Constant;  // the carrier (motion.hpp)
  // Hand-held only: how often a minute the operator swings the sensor sideways 45-100 deg and
  // back at up to 120 deg/s (HandheldProfile::look_arounds_per_minute); 0: never.
  double look_arounds_per_minute = 0.0;
  // > 0: a return needs enough signal: it is detected up to max_range * sqrt(reflectivity *
  // cos(incidence) / full_range_reflectivity) (Lambertian target, 1/r^2), so dark walls seen
  // at grazing angles fade long before max_range. 0: every hit up to max_range (ideal).
  double full_range_reflectivity = 0.0;
  // Depth of the door recesses of the plain corridors (long-, endless-, straight-corridor),
  // metres, > 0: how much the only features along their axis stand out of the walls.
  double recess_depth = kShallowRecess;
  // Where the columns fire within a turn, in columns: 0 fires column c at exactly c / columns
  // of a turn, so every firing lies on a boundary of a range image with the sensor's column
  // count, which no free-running motor does. In [0, 1): that fixed offset (0.5: midway).
  // kRandomFiringPhase: a fresh offset per scan from the seed, as a motor whose phase drifts
  // against the turn's start (a real Velodyne's or Ouster's azimuths).
  double firing_phase = 0.0;
  // Moving people, vehicles and doors (actor_layouts.hpp), placed from `seed` through a stream
  // of their own: the noise and the carrier are the same with or without them. Default: none.
  ActorConfig actors;
  // Hand-held only: replaces the default walking profile (e.g. handheld-aggressive's run), its
  // look-arounds included (look_arounds_per_minute above is then not used).
  std::optional<HandheldProfile> handheld_profile;
};

inline constexpr double kRandomFiringPhase = -1.0;

// The full-range reflectivity of the realistic range model: white targets (90 %) at normal
// incidence reach the sensor's max_range, a 10 % target a third of it (as OS1 data sheets).
inline constexpr double kRealisticFullRangeReflectivity = 0.9;

// Ray-casts a simulated spinning LiDAR moving through an analytic scene. Every column fires at
// its own time t_start + column / columns * scan_period from the sensor pose at that time, so
// scans carry the motion distortion of real ones. No file I/O: see main.cpp for the writer.
class Simulator {
 public:
  Simulator(SceneKind kind, SensorSpec sensor, SimOptions options = {});
  // A realistic preset: its scene, carrier, noise, range model and planned scan count
  // (Preset::Options(seed)); `threads` as SimOptions::threads.
  Simulator(const Preset& preset, SensorSpec sensor, std::uint64_t seed = 1, int threads = 0);

  // Scan `index` (0-based): t_start = ScanStartTime(index), points in firing order. The same
  // index and seed always give the same scan, whatever the thread count. `actor_labels`, if
  // given, gets one PointLabel per point in the same order: 0 static world, 1 on an actor that
  // moved more than 0.3 m in the last second (at the point's firing time), 2 on a resting one.
  Scan SimulateScan(int index, std::vector<std::uint8_t>* actor_labels = nullptr) const;

  // T_world_sensor at absolute time t (the clock of Scan::t_start). The pose of a point is
  // PoseAt(scan.t_start + scan.times[i]), computed exactly like that by the simulator itself.
  Eigen::Isometry3d PoseAt(double t) const;
  double ScanStartTime(int index) const;

  SensorModel sensor_model() const { return ToSensorModel(sensor_); }
  const SensorSpec& sensor() const { return sensor_; }
  const SimOptions& options() const { return options_; }
  SceneKind kind() const { return kind_; }
  MotionKind motion() const { return options_.motion; }
  const Scene& scene() const { return world_.scene; }
  const Trajectory& trajectory() const { return trajectory_; }

  // Actors take the drive time (seconds since t0); these take the clock of Scan::t_start.
  bool has_actors() const { return !actors_.empty(); }
  const ActorSet& actors() const { return actors_; }
  std::vector<ActorFootprint> ActorFootprintsAt(double t) const;
  // Where the actors were during [t_from, t_to]; Vacated(p): they have left p by t_to.
  SweptVolume ActorSweptVolume(double t_from, double t_to) const;
  // The same with SweptVolume's sampling, margin and ground clearance chosen by the caller.
  SweptVolume ActorSweptVolume(double t_from, double t_to, double step, double margin,
                               double clearance) const;
  // Replaces the actors, e.g. with hand-placed ones in a test (their times: drive time).
  void SetActors(ActorSet actors) { actors_ = std::move(actors); }

  static std::vector<std::string> SceneNames();
  // The scene with the chosen carrier applied to its motion (what the constructor uses).
  static World MakeWorld(SceneKind kind, const SensorSpec& sensor, const SimOptions& options);

 private:
  struct Return {
    Eigen::Vector3d point;
    float intensity = 0.0f;
    bool valid = false;
    PointLabel label = PointLabel::Static;
  };
  // R_phase turns every beam by the scan's firing phase; empty: the columns fire on the image's
  // column boundaries. `reach`: the actors that may be seen during the scan.
  void SimulateColumn(int index, int column, double t_start,
                      const std::optional<Eigen::Matrix3d>& R_phase,
                      const std::vector<ActorSet::Reach>& reach, Return* out) const;
  // The column's actors posed at its firing time (empty when none can be hit).
  std::vector<PosedPart> ActorsInColumn(int column, double t, const Eigen::Isometry3d& T_world_sensor,
                                        const std::optional<Eigen::Matrix3d>& R_phase,
                                        const std::vector<ActorSet::Reach>& reach) const;
  double FiringPhase(int index) const;

  SceneKind kind_;
  SensorSpec sensor_;
  SimOptions options_;
  World world_;
  Trajectory trajectory_;
  ActorSet actors_;
  std::vector<Eigen::Vector3d> beam_dirs_;  // [column * rings + ring], sensor frame, unit
};

}  // namespace dammloam::sim
