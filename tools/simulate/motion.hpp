#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tools/simulate/path.hpp"

// How a sensor carrier moves along a scene's path. `constant` is the original simulator (a ramp
// to a constant speed, see Trajectory); the others are seeded random carriers whose speed
// changes all the time, which a constant-velocity motion model cannot predict.
namespace dammloam::sim {

enum class MotionKind { Constant, Handheld, Legged, Wheeled, Vehicle };

// "constant", "handheld", "legged", "wheeled", "vehicle"
std::vector<std::string> MotionNames();
std::optional<MotionKind> ParseMotionKind(std::string_view name);
std::string_view MotionName(MotionKind kind);

// A walking person carrying the sensor in front of the chest. Speeds in m/s, accelerations in
// m/s^2, lengths in metres, angles in degrees, frequencies in Hz, times in seconds. Amplitudes
// are half the peak-to-peak swing. Frequencies and phases are drawn per seed within the ranges.
struct HandheldProfile {
  double speed_min = 1.0, speed_max = 1.4;  // the base walking speed drifts within these
  double speed_time_constant = 6.0;         // of the drift (smoothed random walk)
  double gait_hz_min = 1.8, gait_hz_max = 2.0;  // step frequency
  double gait_speed_modulation = 0.15;      // +-15 % speed at the step frequency
  double accel = 0.7;                       // starting, stopping (raised-cosine peak)
  double lateral_accel = 0.3;               // slows down on curves: U-turn of r 0.5 m at 0.39 m/s
  double stops_per_minute = 1.0;            // at least one stop per run, at random times
  double stop_min = 0.5, stop_max = 2.0;    // standing time of a stop
  double bob = 0.0125;                      // vertical, at the step frequency (2.5 cm p-p)
  double lateral_sway = 0.03;               // sideways, at half the step frequency
  double yaw_sway_deg = 1.5;                // at half the step frequency
  double gait_pitch_deg = 0.4, gait_roll_deg = 0.3;  // at the step frequency
  double tilt_deg = 1.0;                    // slow roll and pitch sway (0.1-0.45 Hz)
  double shake_deg = 0.3;                   // hand shake, RMS per axis, 3 sinusoids in 4-9 Hz
  double shake_hz_min = 4.0, shake_hz_max = 9.0;
  double vibration = 0.0;                   // position vibration (none for a hand)
  double sensor_height = 1.4;               // above the floor
  // Looking around: the operator swings the sensor sideways and back (a turn of the torso),
  // yaw excursions of look_around_deg_min..max at up to look_around_rate_deg_s, at random times.
  double look_arounds_per_minute = 0.0;
  double look_around_deg_min = 45.0, look_around_deg_max = 100.0;
  double look_around_rate_deg_s = 120.0;
  // Drops: the sensor slips from the hand, falls freely drop_height_min..max (the
  // accelerometer reads ~0), is caught at drop_catch_accel and lifted back over drop_recover
  // seconds; at random times after the start ramp.
  int drops = 0;
  double drop_height_min = 0.3, drop_height_max = 0.5;
  double drop_catch_accel = 30.0;  // m/s^2, about 3 g
  double drop_recover = 1.0;
};

// A quadruped robot at a trot: the body pitches and rolls sharply at the trot frequency.
struct LeggedProfile {
  double speed_min = 0.6, speed_max = 0.9;
  double speed_time_constant = 5.0;
  double gait_hz_min = 2.5, gait_hz_max = 3.0;  // trot (diagonal leg pair) frequency
  double gait_speed_modulation = 0.08;
  double accel = 0.6;
  double lateral_accel = 0.3;
  double stops_per_minute = 0.5;            // occasional stops
  double stop_min = 1.0, stop_max = 3.0;
  double bob = 0.0075;                      // 1.5 cm p-p at the trot frequency
  double lateral_sway = 0.01;               // at half the trot frequency
  double yaw_sway_deg = 0.5;
  double gait_pitch_deg = 1.2, gait_roll_deg = 1.2;  // with a second harmonic: sharp peaks
  double tilt_deg = 0.3;
  double shake_deg = 0.1;                   // foot impacts, 3 sinusoids in 8-15 Hz
  double shake_hz_min = 8.0, shake_hz_max = 15.0;
  double vibration = 0.0;
  double sensor_height = 0.6;
};

// A wheeled robot: smooth; target speeds that change a few times per run.
struct WheeledProfile {
  double speed_min = 0.5, speed_max = 1.0;  // target speeds are drawn within these
  double hold_min = 15.0, hold_max = 40.0;  // time between target changes
  double accel = 0.5;                       // peak acceleration of a speed change or stop
  double lateral_accel = 0.3;
  int stops_min = 1, stops_max = 2;         // full stops per run
  double stop_min = 1.0, stop_max = 3.0;
  double vibration = 0.002;                 // vertical and lateral, 3 sinusoids in 8-20 Hz
  double vibration_deg = 0.1;               // roll, pitch, yaw, RMS, same frequencies
  double vibration_hz_min = 8.0, vibration_hz_max = 20.0;
  double sensor_height = 0.8;
};

// A car with the sensor on its roof: target speeds of 5-10 m/s joined by gentle accelerations,
// turns slowed to a comfortable lateral acceleration, and a suspension that pitches the body
// when it accelerates or brakes and rolls it outwards in a turn (both lagging behind the
// acceleration, as springs and dampers do); road roughness shakes it slightly.
struct VehicleProfile {
  double speed_min = 5.0, speed_max = 10.0;  // target speeds are drawn within these
  double hold_min = 8.0, hold_max = 25.0;    // time between target changes
  double accel = 1.2;                        // peak of a speed change, start or stop
  double lateral_accel = 1.5;                // a corner of r 10 m is taken at 3.9 m/s
  int stops_min = 1, stops_max = 2;          // e.g. at a crossing
  double stop_min = 2.0, stop_max = 6.0;
  double vibration = 0.003;                  // vertical and lateral, 3 sinusoids in 6-18 Hz
  double vibration_deg = 0.15;               // roll, pitch, yaw, RMS, same frequencies
  double vibration_hz_min = 6.0, vibration_hz_max = 18.0;
  double pitch_per_accel_deg = 0.4;          // nose down when braking, per m/s^2
  double roll_per_lateral_accel_deg = 0.5;   // outwards in a turn, per m/s^2
  double suspension_time_constant = 0.25;    // s, each of two low-passes on those angles
  double sensor_height = 1.8;
};

// The profile parameters the generator uses, whichever carrier they came from.
struct CarrierParams {
  double speed_min = 1.0, speed_max = 1.0;
  double speed_time_constant = 0.0;  // > 0: smoothed random walk; else piecewise targets
  double hold_min = 20.0, hold_max = 40.0;
  double gait_hz_min = 0.0, gait_hz_max = 0.0, gait_speed_modulation = 0.0;
  bool sharp_gait = false;  // second harmonic on the gait pitch/roll (legged)
  double accel = 0.5, lateral_accel = 0.3;
  double stops_per_minute = 0.0;
  int stops_min = 0, stops_max = 0;
  double stop_min = 1.0, stop_max = 2.0;
  double bob = 0.0, lateral_sway = 0.0, yaw_sway_deg = 0.0;
  double gait_pitch_deg = 0.0, gait_roll_deg = 0.0, tilt_deg = 0.0;
  double shake_deg = 0.0, shake_hz_min = 4.0, shake_hz_max = 9.0;
  bool shake_needs_motion = false;  // shake and vibration fade out while standing
  double vibration = 0.0;
  double sensor_height = 1.2;
  double look_arounds_per_minute = 0.0;  // see HandheldProfile
  double look_around_deg_min = 45.0, look_around_deg_max = 100.0, look_around_rate_deg_s = 120.0;
  double pitch_per_accel_deg = 0.0, roll_per_lateral_accel_deg = 0.0;  // see VehicleProfile
  double suspension_time_constant = 0.25;
  int drops = 0;  // see HandheldProfile
  double drop_height_min = 0.3, drop_height_max = 0.5, drop_catch_accel = 30.0, drop_recover = 1.0;
};
CarrierParams ToParams(const HandheldProfile& p);
CarrierParams ToParams(const LeggedProfile& p);
CarrierParams ToParams(const WheeledProfile& p);
CarrierParams ToParams(const VehicleProfile& p);

// A stretch of path the carrier takes no faster than `max_speed` (a staircase), approached and
// left at the carrier's acceleration.
struct SpeedZone {
  double s_begin = 0.0, s_end = 0.0;  // metres along the path
  double max_speed = 0.5;             // m/s along the path
};

// The carrier's speed along the path and its body motion, precomputed for one seed on a 1 ms
// grid (distance, speed, gait strength), so Eval(t) is a table look-up with cubic Hermite
// interpolation: the distance is C1 in time, whatever the speed does.
class CarrierMotion {
 public:
  struct Sample {
    double s = 0.0;       // distance along the path, metres
    double speed = 0.0;   // ds/dt, m/s
    double gait = 0.0;    // 0 standing .. 1 walking: scales the gait motions
  };
  // Body offsets from the path point, in the path frame (x forward, y left, z up), and angles.
  struct Body {
    double lateral = 0.0, vertical = 0.0;
    double roll = 0.0, pitch = 0.0, yaw = 0.0;  // rad
  };

  // `arrive_time` > 0 on an open path: the base speed is scaled (within 0.8-1.25) so that the
  // end of the path is reached at that time. `duration`: seconds the motion is planned for.
  CarrierMotion(const CarrierParams& params, const Path& path, bool closed, double duration,
                double arrive_time, std::uint64_t seed, const std::vector<SpeedZone>& slow_zones = {});

  Sample Eval(double t) const;
  Body BodyAt(double t, double gait) const;
  const CarrierParams& params() const { return params_; }
  double gait_hz() const { return gait_hz_; }
  double speed_scale() const { return scale_; }

  static constexpr double kDt = 0.001;  // grid step, seconds

 private:
  struct Wave {
    double amplitude = 0.0, omega = 0.0, phase = 0.0;
    double operator()(double t) const;
  };
  double Integrate(double scale, std::vector<double>* s_out, std::vector<double>* v_out) const;
  double SpeedLimit(double s) const;
  void ApplySlowZones(const std::vector<SpeedZone>& zones);
  void ComputeSuspension(const Path& path);
  double Suspension(const std::vector<double>& table, double t) const;

  CarrierParams params_;
  double path_length_ = 0.0;
  bool closed_ = false;
  double gait_hz_ = 0.0, gait_phase_ = 0.0, scale_ = 1.0;
  std::vector<double> base_;      // base speed x stop envelope, per grid step
  std::vector<double> envelope_;  // start ramp x stops, per grid step
  std::vector<double> limit_;     // curve and path-end speed limit, per kLimitDs of path
  std::vector<double> s_, v_, g_, dg_;
  // Suspension pitch and roll (rad) per grid step; empty unless the carrier has a suspension.
  std::vector<double> suspension_pitch_, suspension_roll_;
  // Body motion components.
  double bob_phase_ = 0.0, sway_phase_ = 0.0, yaw_phase_ = 0.0, pitch_phase_ = 0.0, roll_phase_ = 0.0;
  std::vector<Wave> tilt_roll_, tilt_pitch_, shake_roll_, shake_pitch_, shake_yaw_, vib_z_, vib_y_;
  // Yaw out to `amplitude` and back as amplitude (1 - cos(2 pi (t - start) / length)) / 2.
  struct LookAround {
    double start = 0.0, length = 0.0, amplitude = 0.0;
  };
  std::vector<LookAround> look_arounds_;
  struct Drop {
    double start = 0.0, height = 0.0;
  };
  std::vector<Drop> drops_;
  double DropOffset(double t) const;  // vertical, metres (<= 0)
};

}  // namespace dammloam::sim
