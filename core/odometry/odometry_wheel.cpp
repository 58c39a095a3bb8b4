// Wheel odometry in the odometry (issue 55): the samples, their faults, and the integrated
// motion from the previous scan's middle to this one's. How it is used: Predict and PriorFor.
#include "core/odometry/odometry.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace dammloam {

void Odometry::EnableWheel(const WheelUseConfig& config) { wheel_ = config; }

bool Odometry::AddWheel(const WheelSample& sample) {
  const auto reject = [](std::size_t& count) {
    ++count;
    return false;
  };
  if (!wheel_) return reject(wheel_rejected_.not_enabled);
  if (!std::isfinite(sample.t) || !sample.linear_velocity.allFinite() ||
      !sample.angular_velocity.allFinite()) {
    return reject(wheel_rejected_.non_finite);
  }
  if (!wheel_samples_.empty() && sample.t == wheel_samples_.back().t) {
    return reject(wheel_rejected_.duplicate);
  }
  if (!wheel_samples_.empty() && sample.t < wheel_samples_.back().t) {
    return reject(wheel_rejected_.out_of_order);
  }
  if (!(sample.linear_velocity.norm() <= wheel_->max_speed) ||
      !(sample.angular_velocity.cwiseAbs().maxCoeff() <= wheel_->max_yaw_rate)) {
    return reject(wheel_rejected_.absurd);
  }
  wheel_samples_.push_back(sample);
  return true;
}

// From the previous scan's middle to this one's, the interval the prediction spans. The first
// scan has none.
std::optional<WheelTrack> Odometry::TrackWheel(double t_start,
                                               std::optional<WheelCoverage>& why) const {
  if (!wheel_ || !initialised_) return std::nullopt;
  const double half = 0.5 * sensor_.scan_period;
  WheelTrack track = IntegrateWheel(std::span<const WheelSample>(wheel_samples_),
                                    last_stamp_ + half, t_start + half, wheel_->T_sensor_base,
                                    wheel_->integration);
  why = track.coverage;
  if (!track.covered()) return std::nullopt;
  return track;
}

Eigen::Matrix3d Odometry::WheelTranslationInformation(const Frame& frame) const {
  const Eigen::Matrix3d R = T_world_last_.linear();
  const Eigen::Matrix3d covariance =
      R * frame.wheel_interval->translation_covariance * R.transpose();
  return covariance.ldlt().solve(Eigen::Matrix3d::Identity());
}

void Odometry::DropOldWheelSamples() {
  if (wheel_samples_.empty()) return;
  const double oldest = last_stamp_ - wheel_->history;
  const auto keep = std::lower_bound(wheel_samples_.begin(), wheel_samples_.end(), oldest,
                                     [](const WheelSample& s, double t) { return s.t < t; });
  // Erased in batches, as the IMU's.
  if (keep - wheel_samples_.begin() >= 256) wheel_samples_.erase(wheel_samples_.begin(), keep);
}

}  // namespace dammloam
