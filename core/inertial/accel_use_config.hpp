#pragma once

#include "core/inertial/gravity_estimate.hpp"

namespace dammloam {

// How the odometry uses the accelerometer (issues 52, 55; off by default). With a gyro covering
// the interval and gravity learned, the motion prior's velocity changes by what the
// accelerometer integrated instead of staying constant, and its uncertainty grows by
// acceleration_sigma instead of a walker's gait: a registration pulled along by people who
// walk with the carrier, or by a stretch of corridor that does not observe its axis, then has
// to overcome a measured velocity, not a guessed one.
struct AccelUseConfig {
  bool enabled = false;
  // What the integrated force gets wrong, 1 sigma, m/s^2: the gravity and bias estimate, the
  // orientation's tilt error times g (1 mrad: 0.01), the 100 Hz sampling of a hand's shake.
  double acceleration_sigma = 0.1;
  // A reading at or beyond this on any axis is clipped (the ICM-20948's 16 g less a margin).
  double saturation = 15.5 * 9.80665;
  GravityEstimate::Config gravity;
};

}  // namespace dammloam
