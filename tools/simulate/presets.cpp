#include "tools/simulate/presets.hpp"

#include <algorithm>

namespace dammloam::sim {

SimOptions Preset::Options(std::uint64_t seed) const {
  SimOptions options;
  options.seed = seed;
  options.noise_sigma = noise_sigma;
  options.motion = motion;
  options.num_scans = scans;
  options.full_range_reflectivity = full_range_reflectivity;
  options.actors = actors;
  options.look_arounds_per_minute = look_arounds_per_minute;
  options.handheld_profile = handheld_profile;
  return options;
}

namespace {

ActorConfig CorridorPeople() {
  ActorConfig c;
  c.walkers = 9;
  c.close_passes = 4;
  c.groups = 1;
  c.doors = 2;
  return c;
}

// The wheeled carrier zig-zags across most of the corridor: no room for a group beside it.
ActorConfig ZigzagPeople() {
  ActorConfig c;
  c.walkers = 10;
  c.close_passes = 3;
  c.doors = 3;
  return c;
}

ActorConfig CampusCrowd() {
  ActorConfig c;
  c.walkers = 36;
  c.close_passes = 6;
  c.standing = 6;
  c.groups = 1;
  c.traffic = 5;
  c.park_and_leave = true;
  return c;
}

// Running with the sensor: 2.5-3.0 m/s at a 2.6-2.9 Hz stride, bouncing 3 cm, whipping it
// round at up to 3 rad/s eight times a minute, and dropping it once.
HandheldProfile Running() {
  HandheldProfile p;
  p.speed_min = 2.5;
  p.speed_max = 3.0;
  p.gait_hz_min = 2.6;
  p.gait_hz_max = 2.9;
  p.accel = 2.0;
  p.lateral_accel = 2.0;
  p.stops_per_minute = 0.5;
  p.bob = 0.03;
  p.lateral_sway = 0.04;
  p.yaw_sway_deg = 3.0;
  p.gait_pitch_deg = 1.5;
  p.gait_roll_deg = 1.0;
  p.tilt_deg = 2.0;
  p.shake_deg = 0.3;  // as walking: at a run the rate of the shake would exceed the turns
  p.look_arounds_per_minute = 8.0;
  p.look_around_deg_min = 60.0;
  p.look_around_deg_max = 120.0;
  // 2.2 rad/s at a swing's peak; with the stride's sway and the shake the body turns at up to
  // ~3 rad/s (tests/sim/test_inertial.cpp).
  p.look_around_rate_deg_s = 2.2 * 180.0 / 3.14159265358979323846;
  p.drops = 1;
  return p;
}

ActorConfig FollowMe() {
  ActorConfig c;
  c.follow_me = true;
  return c;
}

}  // namespace

const std::vector<Preset>& Presets() {
  static const std::vector<Preset> presets = [] {
    std::vector<Preset> p;
    auto add = [&](std::string name, SceneKind scene, MotionKind motion, int scans, std::string what,
                   ActorConfig actors = {}) {
      Preset preset;
      preset.name = std::move(name);
      preset.scene = scene;
      preset.motion = motion;
      preset.scans = scans;
      preset.what = std::move(what);
      preset.actors = actors;
      p.push_back(std::move(preset));
    };
    add("handheld-corridor", SceneKind::LongCorridor, MotionKind::Handheld, 1700,
        "walking speed changes, stops and a U-turn in a featureless corridor (end walls fade)");
    add("wheeled-corridor", SceneKind::StraightCorridor, MotionKind::Wheeled, 800,
        "smooth speed changes and a stop along a short featureless corridor");
    add("legged-tunnel", SceneKind::Tunnel, MotionKind::Legged, 1500,
        "trot pitch/roll and bobbing in a curved, self-similar tunnel");
    add("handheld-endless", SceneKind::EndlessCorridor, MotionKind::Handheld, 3500,
        "no end wall ever in range: only the motion model constrains the corridor axis");
    add("handheld-campus", SceneKind::Campus, MotionKind::Handheld, 2500,
        "walking outdoors on uneven ground, a 300 m loop back to the start");
    add("wheeled-zigzag", SceneKind::Zigzag, MotionKind::Wheeled, 850,
        "speed changes and stops on a zig-zag through a corridor with doors and pillars");
    // The same walks with moving actors (labels/ beside the scans).
    add("handheld-corridor-people", SceneKind::LongCorridor, MotionKind::Handheld, 1700,
        "handheld-corridor with people walking both ways (some within 1 m), a group keeping "
        "pace beside the walker and two doors opening",
        CorridorPeople());
    add("wheeled-zigzag-people", SceneKind::Zigzag, MotionKind::Wheeled, 850,
        "wheeled-zigzag with people walking both ways, stopping and turning, and doors opening",
        ZigzagPeople());
    add("campus-crowd", SceneKind::Campus, MotionKind::Handheld, 2500,
        "handheld-campus with 40+ pedestrians, a group alongside, cars going round, one car "
        "parking and a parked one leaving",
        CampusCrowd());
    add("follow-me", SceneKind::LongCorridor, MotionKind::Handheld, 1700,
        "handheld-corridor behind a person walking 2 m ahead the whole way: the view ahead "
        "moves with the walker",
        FollowMe());
    // Large motion between scans (issue 58): every 2nd-5th scan of it is the hard case.
    add("handheld-look-around", SceneKind::Zigzag, MotionKind::Handheld, 1000,
        "a hand-held walk through the zigzag whose operator swings the sensor 45-100 deg sideways "
        "and back at up to 120 deg/s, six times a minute");
    p.back().look_arounds_per_minute = 6.0;
    // Inertial presets (issue 55): the motions an IMU or wheel odometry is there for.
    add("handheld-aggressive", SceneKind::Campus, MotionKind::Handheld, 1300,
        "running round the campus loop at 2.5-3 m/s, whipping the sensor round at up to 3 rad/s "
        "eight times a minute, and one drop of 0.3-0.5 m (free fall, caught at 3 g)");
    p.back().handheld_profile = Running();
    add("wheeled-endless", SceneKind::EndlessCorridor, MotionKind::Wheeled, 5000,
        "a wheeled robot 200 m out and back in the endless corridor: only the motion model (or "
        "wheel odometry) constrains its axis");
    // Drift and loop-closure presets (issue 53): long enough for odometry to drift, with true
    // revisits and look-alike places that are not revisits.
    add("campus-long-handheld", SceneKind::CampusLong, MotionKind::Handheld, 12000,
        "a 1.55 km walk over a campus grid (a park and an open field on the way, rolling ground) "
        "revisiting five streets and crossings, three of them in the opposite direction");
    add("campus-long-vehicle", SceneKind::CampusLong, MotionKind::Vehicle, 2600,
        "the campus-long route driven at 5-10 m/s with suspension pitch/roll, corners of r 10 m");
    add("two-floor", SceneKind::TwoFloor, MotionKind::Handheld, 2500,
        "round a ring corridor, up a staircase, round the identical corridor 3 m above: a loop "
        "between the floors is false; each floor's start is revisited");
    add("warehouse-aisles", SceneKind::Warehouse, MotionKind::Wheeled, 4000,
        "a robot up and down five identical rack aisles, then two of them again (one against "
        "its first direction): perceptual aliasing");
    return p;
  }();
  return presets;
}

std::vector<std::string> PresetNames() {
  std::vector<std::string> names;
  for (const Preset& p : Presets()) names.push_back(p.name);
  return names;
}

std::optional<Preset> FindPreset(std::string_view name) {
  const auto& all = Presets();
  const auto it = std::find_if(all.begin(), all.end(), [&](const Preset& p) { return p.name == name; });
  if (it == all.end()) return std::nullopt;
  return *it;
}

double DefaultNoise(MotionKind motion) { return motion == MotionKind::Constant ? 0.01 : 0.015; }

double DefaultFullRangeReflectivity(MotionKind motion) {
  return motion == MotionKind::Constant ? 0.0 : kRealisticFullRangeReflectivity;
}

}  // namespace dammloam::sim
