#include "tools/simulate/trajectory.hpp"
#include "tools/simulate/angles.hpp"

#include <cmath>
#include <numbers>

namespace dammloam::sim {

namespace {
double Wave(double amplitude, double period, double t, double phase = 0.0) {
  return amplitude * std::sin(2.0 * std::numbers::pi * t / period + phase);
}
}  // namespace

double FloorHeight(const std::vector<FloorRise>& rises, double s) {
  double z = 0.0;
  for (const FloorRise& rise : rises) {
    const double length = rise.s_end - rise.s_begin;
    if (s >= rise.s_end) {
      z += rise.height;
    } else if (s > rise.s_begin && length > 0.0) {
      const double u = (s - rise.s_begin) / length;
      z += rise.height * u * u * (3.0 - 2.0 * u);  // smoothstep: no kink where the flight starts
    }
  }
  return z;
}

CarrierParams CarrierParamsOf(const MotionSpec& spec) {
  switch (spec.kind) {
    case MotionKind::Legged: return ToParams(spec.legged);
    case MotionKind::Wheeled: return ToParams(spec.wheeled);
    case MotionKind::Vehicle: return ToParams(spec.vehicle);
    case MotionKind::Constant:
    case MotionKind::Handheld: break;
  }
  return ToParams(spec.handheld);
}

Trajectory::Trajectory(MotionSpec spec) : spec_(std::move(spec)) {
  if (spec_.kind != MotionKind::Constant) {
    carrier_ = std::make_shared<const CarrierMotion>(CarrierParamsOf(spec_), spec_.path, spec_.closed,
                                                     spec_.duration, spec_.arrive_time, spec_.seed,
                                                     spec_.slow_zones);
  }
}

// Raised-cosine speed profile v(t) = v (1 - cos(pi t / T)) / 2 up to T = ramp_up, then v: the
// drive starts from rest with continuous acceleration, as real runs do.
double Trajectory::Distance(double t) const {
  const double v = spec_.speed, T = spec_.ramp_up;
  if (t <= 0.0) return 0.0;
  if (T <= 0.0) return v * t;
  if (t >= T) return 0.5 * v * T + v * (t - T);
  return 0.5 * v * (t - T / std::numbers::pi * std::sin(std::numbers::pi * t / T));
}

double Trajectory::PathDistance(double t) const {
  return carrier_ ? carrier_->Eval(t).s : Distance(t);
}

Eigen::Vector3d Trajectory::Position(double t, double* path_heading) const {
  const double s = Distance(t);
  const Path::State base = spec_.path.At(s, spec_.closed);
  if (path_heading) *path_heading = base.heading;
  const Eigen::Vector2d left(-std::sin(base.heading), std::cos(base.heading));
  const double lateral =
      Wave(spec_.zigzag_amplitude, spec_.zigzag_wavelength, s) +
      Wave(spec_.wobble.lateral, spec_.wobble.lateral_period, t, 0.4);
  const Eigen::Vector2d xy = base.position + lateral * left;
  const double ground = (spec_.ground ? spec_.ground->Height(xy.x(), xy.y()) : 0.0) + FloorHeight(spec_.floor_rises, s);
  const double z = ground + spec_.sensor_height +
                   Wave(spec_.wobble.vertical, spec_.wobble.vertical_period, t, 1.1);
  return {xy.x(), xy.y(), z};
}

Eigen::Isometry3d Trajectory::Pose(double t) const {
  if (carrier_) return CarrierPose(t);
  double path_heading = 0.0;
  const Eigen::Vector3d p = Position(t, &path_heading);
  // Yaw follows the path and the zig-zag (its slope per metre of path, so it stays defined while
  // standing still); the time-based lateral wobble sways the sensor without turning it.
  const double s = Distance(t);
  const double zigzag_slope =
      spec_.zigzag_wavelength > 0.0
          ? spec_.zigzag_amplitude * 2.0 * std::numbers::pi / spec_.zigzag_wavelength *
                std::cos(2.0 * std::numbers::pi * s / spec_.zigzag_wavelength)
          : 0.0;
  const double yaw_travel = path_heading + std::atan(zigzag_slope);
  const double yaw = yaw_travel + kDegToRad * Wave(spec_.wobble.yaw_deg, spec_.wobble.yaw_period, t, 2.0);

  // Ground slope along (pitch, nose up when rising) and across (roll, left side up) the heading.
  double pitch = 0.0, roll = 0.0;
  if (spec_.ground) {
    const Eigen::Vector2d g = spec_.ground->Gradient(p.x(), p.y());
    const Eigen::Vector2d forward(std::cos(yaw), std::sin(yaw)), left(-forward.y(), forward.x());
    pitch = -std::atan(g.dot(forward));
    roll = std::atan(g.dot(left));
  }
  pitch += kDegToRad * Wave(spec_.wobble.pitch_deg, spec_.wobble.pitch_period, t, 0.7);
  roll += kDegToRad * Wave(spec_.wobble.roll_deg, spec_.wobble.roll_period, t, 2.9);

  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = p;
  return T;
}

// The carrier's distance along the path, the zig-zag of the scene, the body motion on top.
Eigen::Isometry3d Trajectory::CarrierPose(double t) const {
  const CarrierMotion::Sample sample = carrier_->Eval(t);
  return CarrierPoseWith(sample, carrier_->BodyAt(t, sample.gait));
}

Eigen::Isometry3d Trajectory::ChassisPose(double t) const {
  if (!carrier_) return Pose(t);
  return CarrierPoseWith(carrier_->Eval(t), CarrierMotion::Body{});
}

Eigen::Isometry3d Trajectory::CarrierPoseWith(const CarrierMotion::Sample& sample,
                                              const CarrierMotion::Body& body) const {
  const double s = sample.s;
  const Path::State base = spec_.path.At(s, spec_.closed);
  const Eigen::Vector2d left(-std::sin(base.heading), std::cos(base.heading));
  const double lateral = Wave(spec_.zigzag_amplitude, spec_.zigzag_wavelength, s) + body.lateral;
  const Eigen::Vector2d xy = base.position + lateral * left;
  const double ground = (spec_.ground ? spec_.ground->Height(xy.x(), xy.y()) : 0.0) + FloorHeight(spec_.floor_rises, s);
  const Eigen::Vector3d p(xy.x(), xy.y(), ground + spec_.sensor_height + body.vertical);

  const double zigzag_slope =
      spec_.zigzag_wavelength > 0.0
          ? spec_.zigzag_amplitude * 2.0 * std::numbers::pi / spec_.zigzag_wavelength *
                std::cos(2.0 * std::numbers::pi * s / spec_.zigzag_wavelength)
          : 0.0;
  const double yaw = base.heading + std::atan(zigzag_slope) + body.yaw;
  double pitch = body.pitch, roll = body.roll;
  if (spec_.ground) {
    const Eigen::Vector2d g = spec_.ground->Gradient(p.x(), p.y());
    const Eigen::Vector2d forward(std::cos(yaw), std::sin(yaw)), side(-forward.y(), forward.x());
    pitch -= std::atan(g.dot(forward));
    roll += std::atan(g.dot(side));
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = p;
  return T;
}

}  // namespace dammloam::sim
