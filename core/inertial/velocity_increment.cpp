#include "core/inertial/velocity_increment.hpp"

#include <algorithm>
#include <cmath>

namespace dammloam {
namespace {

struct Reading {
  Eigen::Vector3d rate, force;  // IMU frame
};

// Linear between the bracketing samples, held beyond the outer ones (the gyro's track has
// already checked that no step there is longer than its max_gap).
Reading ReadingAt(std::span<const ImuSample> samples, double t) {
  const auto by_time = [](const ImuSample& s, double u) { return s.t < u; };
  const auto after = std::lower_bound(samples.begin(), samples.end(), t, by_time);
  if (after == samples.begin()) return {after->angular_velocity, after->linear_acceleration};
  if (after == samples.end()) {
    const ImuSample& last = samples.back();
    return {last.angular_velocity, last.linear_acceleration};
  }
  const ImuSample& a = *(after - 1);
  const ImuSample& b = *after;
  const double f = (t - a.t) / (b.t - a.t);
  return {a.angular_velocity + f * (b.angular_velocity - a.angular_velocity),
          a.linear_acceleration + f * (b.linear_acceleration - a.linear_acceleration)};
}

AccelCoverage CheckForces(std::span<const ImuSample> samples, double t0, double t1,
                          double saturation) {
  const auto by_time = [](const ImuSample& s, double u) { return s.t < u; };
  auto first = std::lower_bound(samples.begin(), samples.end(), t0, by_time);
  if (first != samples.begin()) --first;
  auto last = std::lower_bound(samples.begin(), samples.end(), t1, by_time);
  if (last == samples.end()) --last;
  for (auto s = first; s <= last; ++s) {
    if (!s->linear_acceleration.allFinite()) return AccelCoverage::kNonFinite;
    if (s->linear_acceleration.cwiseAbs().maxCoeff() >= saturation) return AccelCoverage::kSaturated;
  }
  return AccelCoverage::kCovered;
}

}  // namespace

const char* Name(AccelCoverage coverage) {
  switch (coverage) {
    case AccelCoverage::kCovered: return "covered";
    case AccelCoverage::kNoRotation: return "no_gyro_track";
    case AccelCoverage::kNonFinite: return "non_finite";
    case AccelCoverage::kSaturated: return "saturated";
  }
  return "unknown";
}

namespace {

// The integration both results share: visit(t, increment so far, its bias_to_displacement) at
// every knot after t0.
template <typename Visit>
VelocityIncrement Integrate(std::span<const ImuSample> samples, const GyroTrack& rotation,
                            const Eigen::Isometry3d& T_sensor_imu, double saturation, Visit visit) {
  VelocityIncrement increment;
  if (!rotation.covered() || samples.empty()) return increment;
  const double t0 = rotation.t0(), t1 = rotation.t1();
  increment.coverage = CheckForces(samples, t0, t1, saturation);
  if (!increment.covered()) return increment;
  increment.duration = t1 - t0;

  const Eigen::Matrix3d R_si = T_sensor_imu.linear();
  // The sensor's origin seen from the IMU, sensor frame.
  const Eigen::Vector3d lever = -T_sensor_imu.translation();
  std::vector<double> knots{t0};
  for (const ImuSample& s : samples) {
    if (s.t > t0 && s.t < t1) knots.push_back(s.t);
  }
  knots.push_back(t1);

  const auto force_at = [&](const Reading& r) {
    const Eigen::Vector3d w = R_si * r.rate;
    return Eigen::Vector3d(R_si * r.force + w.cross(w.cross(lever)));
  };
  Reading before = ReadingAt(samples, t0);
  Eigen::Matrix3d R_before = rotation.At(t0);
  Eigen::Vector3d f_before = R_before * force_at(before);
  Eigen::Matrix3d bias_to_displacement = Eigen::Matrix3d::Zero();
  for (std::size_t k = 1; k < knots.size(); ++k) {
    const double h = knots[k] - knots[k - 1];
    if (!(h > 0.0)) continue;
    const Reading after = ReadingAt(samples, knots[k]);
    const Eigen::Matrix3d R_after = rotation.At(knots[k]);
    const Eigen::Vector3d f_after = R_after * force_at(after);
    // The tangential part, alpha x lever, integrates to the change of rate across the step.
    const Eigen::Matrix3d R_mid = 0.5 * (R_before + R_after);
    const Eigen::Vector3d tangential = R_mid * (R_si * (after.rate - before.rate)).cross(lever);
    const Eigen::Vector3d dv = 0.5 * h * (f_before + f_after) + tangential;
    const Eigen::Matrix3d db = 0.5 * h * (R_before + R_after) * R_si;
    increment.displacement += h * increment.velocity + 0.5 * h * dv;
    increment.velocity += dv;
    bias_to_displacement += h * increment.bias_to_velocity + 0.5 * h * db;
    increment.bias_to_velocity += db;
    visit(knots[k], increment, bias_to_displacement);
    before = after;
    R_before = R_after;
    f_before = f_after;
  }
  return increment;
}

}  // namespace

VelocityIncrement IntegrateSpecificForce(std::span<const ImuSample> samples, const GyroTrack& rotation,
                                         const Eigen::Isometry3d& T_sensor_imu, double saturation) {
  return Integrate(samples, rotation, T_sensor_imu, saturation,
                   [](double, const VelocityIncrement&, const Eigen::Matrix3d&) {});
}

std::optional<AccelerationTrack> TrackAcceleration(std::span<const ImuSample> samples,
                                                   const GyroTrack& rotation,
                                                   const Eigen::Isometry3d& T_sensor_imu,
                                                   double saturation, const Eigen::Vector3d& bias,
                                                   const Eigen::Vector3d& gravity_start) {
  AccelerationTrack track;
  track.times.push_back(rotation.t0());
  track.displacement.push_back(Eigen::Vector3d::Zero());
  track.velocity.push_back(Eigen::Vector3d::Zero());
  const VelocityIncrement increment = Integrate(
      samples, rotation, T_sensor_imu, saturation,
      [&](double t, const VelocityIncrement& so_far, const Eigen::Matrix3d& bias_to_displacement) {
        const double tau = t - rotation.t0();
        track.times.push_back(t);
        track.displacement.push_back(so_far.displacement - bias_to_displacement * bias +
                                     0.5 * tau * tau * gravity_start);
        track.velocity.push_back(so_far.velocity - so_far.bias_to_velocity * bias +
                                 tau * gravity_start);
      });
  if (!increment.covered()) return std::nullopt;
  return track;
}

Eigen::Vector3d AccelerationTrack::Interpolate(const std::vector<Eigen::Vector3d>& values,
                                               double t) const {
  if (t <= times.front()) return values.front();
  if (t >= times.back()) return values.back();
  const std::size_t k =
      static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
  const double f = (t - times[k - 1]) / (times[k] - times[k - 1]);
  return values[k - 1] + f * (values[k] - values[k - 1]);
}

}  // namespace dammloam
