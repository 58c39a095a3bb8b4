#include "core/inertial/gyro_integration.hpp"

#include <algorithm>
#include <cmath>

#include "core/geometry/se3.hpp"

namespace dammloam {
namespace {

// The samples that bracket [t0, t1]: the last at or before t0 (else the first) to the first at
// or after t1 (else the last).
struct Bracket {
  std::size_t first = 0, last = 0;
};

Bracket BracketOf(std::span<const ImuSample> samples, double t0, double t1) {
  const auto by_time = [](const ImuSample& s, double t) { return s.t < t; };
  const auto after_t0 = std::lower_bound(samples.begin(), samples.end(), t0, by_time);
  std::size_t first = static_cast<std::size_t>(after_t0 - samples.begin());
  if (first == samples.size()) {
    first = samples.size() - 1;
  } else if (samples[first].t > t0 && first > 0) {
    --first;
  }
  const auto at_t1 = std::lower_bound(samples.begin(), samples.end(), t1, by_time);
  std::size_t last = static_cast<std::size_t>(at_t1 - samples.begin());
  if (last == samples.size()) last = samples.size() - 1;
  return {first, last};
}

// Every step from t0 through the samples to t1 is at most max_gap (beyond the outer samples
// the rate is held).
bool Contiguous(std::span<const ImuSample> samples, const Bracket& b, double t0, double t1,
                double max_gap) {
  if (samples[b.first].t - t0 > max_gap || t1 - samples[b.last].t > max_gap) return false;
  for (std::size_t k = b.first + 1; k <= b.last; ++k) {
    if (samples[k].t - samples[k - 1].t > max_gap) return false;
  }
  return true;
}

GyroCoverage CheckReadings(std::span<const ImuSample> samples, const Bracket& b,
                           double saturation_rate) {
  for (std::size_t k = b.first; k <= b.last; ++k) {
    const Eigen::Vector3d& w = samples[k].angular_velocity;
    if (!w.allFinite()) return GyroCoverage::kNonFinite;
    if (w.cwiseAbs().maxCoeff() >= saturation_rate) return GyroCoverage::kSaturated;
  }
  return GyroCoverage::kCovered;
}

// The raw rate at t, linearly interpolated between the bracketing samples, held beyond them.
Eigen::Vector3d RawRateAt(std::span<const ImuSample> samples, const Bracket& b, double t) {
  if (t <= samples[b.first].t) return samples[b.first].angular_velocity;
  if (t >= samples[b.last].t) return samples[b.last].angular_velocity;
  std::size_t k = b.first;
  while (k + 1 < b.last && samples[k + 1].t <= t) ++k;
  const ImuSample& a = samples[k];
  const ImuSample& c = samples[k + 1];
  const double s = (t - a.t) / (c.t - a.t);
  return (1.0 - s) * a.angular_velocity + s * c.angular_velocity;
}

// The rotation vector of a step of length h over which the rate goes linearly from wa to wb:
// the mean rate, plus the coning term of the rate's turn within the step (second order).
Eigen::Vector3d StepRotation(const Eigen::Vector3d& wa, const Eigen::Vector3d& wb, double h) {
  return 0.5 * h * (wa + wb) + (h * h / 12.0) * wa.cross(wb);
}

Eigen::Matrix3d TrackCovariance(const GyroCalibration& c, double T) {
  const double white = c.noise_density * c.noise_density * T;
  const double walk = c.bias_random_walk * c.bias_random_walk * T * T * T / 3.0;
  const Eigen::Matrix3d bias = c.R_sensor_imu * c.bias_covariance * c.R_sensor_imu.transpose();
  return (white + walk) * Eigen::Matrix3d::Identity() + T * T * bias;
}

}  // namespace

const char* Name(GyroCoverage coverage) {
  switch (coverage) {
    case GyroCoverage::kCovered: return "covered";
    case GyroCoverage::kNoSamples: return "no_samples";
    case GyroCoverage::kGap: return "gap";
    case GyroCoverage::kSaturated: return "saturated";
    case GyroCoverage::kNonFinite: return "non_finite";
  }
  return "unknown";
}

Eigen::Matrix3d GyroTrack::At(double t) const {
  if (!covered() || times_.empty()) return Eigen::Matrix3d::Identity();
  t = std::clamp(t, t0_, t1_);
  const auto above = std::upper_bound(times_.begin(), times_.end(), t);
  const std::size_t k = above == times_.begin() ? 0 : static_cast<std::size_t>(above - times_.begin()) - 1;
  if (k + 1 >= times_.size()) return rotations_.back();
  const double h = t - times_[k];
  if (!(h > 0.0)) return rotations_[k];
  const double s = h / (times_[k + 1] - times_[k]);
  const Eigen::Vector3d w_t = (1.0 - s) * rates_[k] + s * rates_[k + 1];
  return rotations_[k] * ExpSO3(StepRotation(rates_[k], w_t, h));
}

GyroTrack IntegrateGyro(std::span<const ImuSample> samples, double t0, double t1,
                        const GyroCalibration& calibration, const GyroIntegrationConfig& config) {
  GyroTrack track;
  track.t0_ = t0;
  track.t1_ = t1;
  if (samples.empty() || !(t1 >= t0)) return track;  // kNoSamples
  // The stream has not reached t1 (or has stopped), or begins after t0: nothing to bridge.
  if (samples.back().t < t1 - config.max_gap || samples.front().t > t0 + config.max_gap) {
    return track;
  }
  const Bracket b = BracketOf(samples, t0, t1);
  if (!Contiguous(samples, b, t0, t1, config.max_gap)) {
    track.coverage_ = GyroCoverage::kGap;
    return track;
  }
  track.coverage_ = CheckReadings(samples, b, config.saturation_rate);
  if (!track.covered()) return track;

  // Knots and their bias-corrected sensor-frame rates.
  track.times_.push_back(t0);
  for (std::size_t k = b.first; k <= b.last; ++k) {
    if (samples[k].t > t0 && samples[k].t < t1) track.times_.push_back(samples[k].t);
  }
  if (t1 > t0) track.times_.push_back(t1);
  for (double t : track.times_) {
    track.rates_.push_back(calibration.R_sensor_imu * (RawRateAt(samples, b, t) - calibration.bias));
  }
  track.rotations_.push_back(Eigen::Matrix3d::Identity());
  for (std::size_t k = 1; k < track.times_.size(); ++k) {
    const double h = track.times_[k] - track.times_[k - 1];
    track.rotations_.push_back(track.rotations_.back() *
                               ExpSO3(StepRotation(track.rates_[k - 1], track.rates_[k], h)));
  }
  track.covariance_ = TrackCovariance(calibration, t1 - t0);
  return track;
}

}  // namespace dammloam
