#include "core/inertial/wheel_integration.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/geometry/se3.hpp"

namespace dammloam {
namespace {

// The samples that bracket [t0, t1]: the last at or before t0 (else the first) to the first at
// or after t1 (else the last).
struct WheelBracket {
  std::size_t first = 0, last = 0;
};

WheelBracket WheelBracketOf(std::span<const WheelSample> samples, double t0, double t1) {
  const auto by_time = [](const WheelSample& s, double t) { return s.t < t; };
  std::size_t first = static_cast<std::size_t>(
      std::lower_bound(samples.begin(), samples.end(), t0, by_time) - samples.begin());
  if (first == samples.size()) {
    first = samples.size() - 1;
  } else if (samples[first].t > t0 && first > 0) {
    --first;
  }
  std::size_t last = static_cast<std::size_t>(
      std::lower_bound(samples.begin(), samples.end(), t1, by_time) - samples.begin());
  if (last == samples.size()) last = samples.size() - 1;
  return {first, last};
}

bool WheelContiguous(std::span<const WheelSample> samples, const WheelBracket& b, double t0, double t1,
                double max_gap) {
  if (samples[b.first].t - t0 > max_gap || t1 - samples[b.last].t > max_gap) return false;
  for (std::size_t k = b.first + 1; k <= b.last; ++k) {
    if (samples[k].t - samples[k - 1].t > max_gap) return false;
  }
  return true;
}

// The base twist [v; w] at t, linearly interpolated between the bracketing samples, held
// beyond them.
Vector6d WheelTwistAt(std::span<const WheelSample> samples, const WheelBracket& b, double t) {
  const auto twist = [](const WheelSample& s) {
    Vector6d xi;
    xi << s.linear_velocity, s.angular_velocity;
    return xi;
  };
  if (t <= samples[b.first].t) return twist(samples[b.first]);
  if (t >= samples[b.last].t) return twist(samples[b.last]);
  std::size_t k = b.first;
  while (k + 1 < b.last && samples[k + 1].t <= t) ++k;
  const WheelSample& a = samples[k];
  const WheelSample& c = samples[k + 1];
  const double s = (t - a.t) / (c.t - a.t);
  return (1.0 - s) * twist(a) + s * twist(c);
}

// What the interval's integrals say about its errors (WheelNoise), as a covariance of the
// translation in the base frame at t0 and a variance of the turn.
struct WheelIntegrals {
  double duration = 0.0;
  double sample_period = 0.0;
  double distance = 0.0;       // m, path length
  double turn = 0.0;           // rad, about the base's z
  double lateral_accel = 0.0;  // integral of |v w_z| dt, m/s
};

void WheelCovariance(const WheelIntegrals& in, const Eigen::Vector3d& chord, const WheelNoise& n,
                Eigen::Matrix3d& translation, double& yaw_variance) {
  // White noise per sample: the mean over the interval of samples h apart averages T / h of
  // them; an interval shorter than h sees one.
  const double white = in.duration * std::min(in.duration, in.sample_period);
  const double scale_turn = n.yaw_rate_scale * in.turn;
  const double slip_turn = n.yaw_slip * in.lateral_accel;
  yaw_variance = n.yaw_rate_noise * n.yaw_rate_noise * white + scale_turn * scale_turn +
                 slip_turn * slip_turn;
  const double scale_distance = n.speed_scale * in.distance;
  const double along = n.speed_noise * n.speed_noise * white + scale_distance * scale_distance +
                       n.longitudinal_model_error * n.longitudinal_model_error;
  // The heading error grows through the interval, so the path bends away by about half the
  // distance times the final error; sliding outwards in a turn adds to it.
  const double bend = 0.5 * in.distance;
  const double slide = n.lateral_slip * in.lateral_accel;
  const double across = bend * bend * yaw_variance + slide * slide + n.vibration * n.vibration;
  const double up = n.vibration * n.vibration;
  Eigen::Vector3d forward(chord.x(), chord.y(), 0.0);
  forward = forward.norm() > 1e-9 ? forward.normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward);
  translation = along * forward * forward.transpose() + across * left * left.transpose() +
                up * Eigen::Vector3d::UnitZ() * Eigen::Vector3d::UnitZ().transpose();
}

}  // namespace

const char* Name(WheelCoverage coverage) {
  switch (coverage) {
    case WheelCoverage::kCovered: return "covered";
    case WheelCoverage::kNoSamples: return "no_samples";
    case WheelCoverage::kGap: return "gap";
  }
  return "unknown";
}

WheelTrack IntegrateWheel(std::span<const WheelSample> samples, double t0, double t1,
                          const Eigen::Isometry3d& T_sensor_base,
                          const WheelIntegrationConfig& config) {
  WheelTrack track;
  track.t0 = t0;
  track.t1 = t1;
  if (samples.empty() || !(t1 >= t0)) return track;  // kNoSamples
  if (samples.back().t < t1 - config.max_gap || samples.front().t > t0 + config.max_gap) {
    return track;
  }
  const WheelBracket b = WheelBracketOf(samples, t0, t1);
  if (!WheelContiguous(samples, b, t0, t1, config.max_gap)) {
    track.coverage = WheelCoverage::kGap;
    return track;
  }
  track.coverage = WheelCoverage::kCovered;

  std::vector<double> knots{t0};
  for (std::size_t k = b.first; k <= b.last; ++k) {
    if (samples[k].t > t0 && samples[k].t < t1) knots.push_back(samples[k].t);
  }
  if (t1 > t0) knots.push_back(t1);
  WheelIntegrals in;
  in.duration = t1 - t0;
  in.sample_period = b.last > b.first ? (samples[b.last].t - samples[b.first].t) /
                                            static_cast<double>(b.last - b.first)
                                      : config.max_gap;
  Eigen::Isometry3d T_b0_b = Eigen::Isometry3d::Identity();
  Vector6d previous = WheelTwistAt(samples, b, knots.front());
  for (std::size_t k = 1; k < knots.size(); ++k) {
    const double h = knots[k] - knots[k - 1];
    const Vector6d next = WheelTwistAt(samples, b, knots[k]);
    const Vector6d mean = 0.5 * (previous + next);
    T_b0_b = T_b0_b * ExpSE3(h * mean);
    in.distance += h * mean.head<3>().norm();
    in.turn += h * mean(5);
    in.lateral_accel += h * std::abs(mean.head<3>().norm() * mean(5));
    previous = next;
  }
  in.turn = std::abs(in.turn);
  track.distance = in.distance;
  track.motion = Normalized(T_sensor_base * T_b0_b * T_sensor_base.inverse());
  Eigen::Matrix3d base_covariance;
  WheelCovariance(in, T_b0_b.translation(), config.noise, base_covariance, track.yaw_variance);
  const Eigen::Matrix3d R = T_sensor_base.linear();
  track.translation_covariance = R * base_covariance * R.transpose();
  return track;
}

}  // namespace dammloam
