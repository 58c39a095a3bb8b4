#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "tools/simulate/motion.hpp"
#include "tools/simulate/path.hpp"
#include "tools/simulate/primitives.hpp"

namespace dammloam::sim {

// Small periodic disturbances of a hand-held or wheeled platform; amplitudes in metres/degrees,
// periods in seconds. Incommensurate periods keep the motion from repeating exactly.
struct Wobble {
  double lateral = 0.03, lateral_period = 6.3;
  double vertical = 0.01, vertical_period = 1.7;
  double roll_deg = 0.6, roll_period = 2.3;
  double pitch_deg = 0.5, pitch_period = 1.9;
  double yaw_deg = 0.8, yaw_period = 4.1;
};

// The floor under the path rises by `height` between two path distances (a staircase climbed
// from s_begin to s_end; negative: walked down). Smooth in between, so the carrier's height
// and its rate stay continuous.
struct FloorRise {
  double s_begin = 0.0, s_end = 0.0;  // metres along the path
  double height = 0.0;                // metres
};
// The sum of every rise at path distance s.
double FloorHeight(const std::vector<FloorRise>& rises, double s);

struct MotionSpec {
  Path path;
  bool closed = false;        // repeat the path (a loop) instead of stopping at its end
  double speed = 1.0;         // m/s along the path
  double ramp_up = 2.0;       // s to reach `speed` from rest (smooth), as a robot starting a run
  double sensor_height = 1.2; // metres above the ground under the sensor
  double zigzag_amplitude = 0.0;   // lateral sine offset from the path, metres
  double zigzag_wavelength = 10.0; // metres of path per zig-zag period
  Wobble wobble;
  std::optional<Heightfield> ground;  // z and roll/pitch follow it when set (else ground z = 0)

  // Carrier (see motion.hpp). Constant: `speed`, `ramp_up` and `wobble` above, as always.
  // Otherwise the profile of `kind` drives the speed along the path and the body motion (the
  // wobble is not used, the zig-zag is), seeded by `seed`, planned for `duration` seconds.
  MotionKind kind = MotionKind::Constant;
  std::uint64_t seed = 1;
  double duration = 60.0;
  double arrive_time = 0.0;  // > 0: reach the end of an open path at this time (see CarrierMotion)
  HandheldProfile handheld;
  LeggedProfile legged;
  WheeledProfile wheeled;
  VehicleProfile vehicle;
  // Staircases on the path (every carrier climbs them) and where a carrier that is not
  // `constant` slows down.
  std::vector<FloorRise> floor_rises;
  std::vector<SpeedZone> slow_zones;
};

// The chosen carrier's parameters (Constant: none; returns the handheld ones).
CarrierParams CarrierParamsOf(const MotionSpec& spec);

// The sensor pose as a smooth function of time. Yaw follows the direction of travel, roll and
// pitch follow the ground slope, plus the wobble.
class Trajectory {
 public:
  explicit Trajectory(MotionSpec spec);

  // T_world_sensor at t seconds after the start of the drive.
  Eigen::Isometry3d Pose(double t) const;
  const MotionSpec& spec() const { return spec_; }
  // Arc length along spec().path travelled after t seconds, whichever carrier moves.
  double PathDistance(double t) const;
  // The carrier's chassis without its body motion (sway, shake, vibration, suspension): where
  // the wheels take it, at the sensor's nominal height, sensor axes. What wheel odometry
  // measures. Constant motion: Pose(t).
  Eigen::Isometry3d ChassisPose(double t) const;
  // The precomputed carrier (null for constant motion).
  const CarrierMotion* carrier() const { return carrier_.get(); }

 private:
  Eigen::Vector3d Position(double t, double* path_heading = nullptr) const;
  double Distance(double t) const;  // arc length travelled along the path after t seconds

  Eigen::Isometry3d CarrierPose(double t) const;
  Eigen::Isometry3d CarrierPoseWith(const CarrierMotion::Sample& sample, const CarrierMotion::Body& body) const;

  MotionSpec spec_;
  std::shared_ptr<const CarrierMotion> carrier_;  // shared: copies of a simulator stay cheap
};

}  // namespace dammloam::sim
