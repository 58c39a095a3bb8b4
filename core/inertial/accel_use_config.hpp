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
  // Slow errors (a tilt that drifts, the bias) the gravity fit takes up. At 0.1 a person walking
  // 2 m ahead still slowed the estimate by 15 % over 16 s (follow-me seed 1: 2.9 m APE; 1.1 m at
  // 0.03, 1.6 m at 0.05; the static corridor unchanged).
  double acceleration_sigma = 0.03;
  // Deskew each scan along the twice-integrated acceleration as well (once gravity has its first
  // estimate), not along a constant velocity: a running bounce's vertical acceleration bends a
  // 0.1 s scan by about a centimetre, which the registration cannot take out and which the
  // reported scan-start pose inherits.
  bool deskew = true;
  // A reading at or beyond this on any axis is clipped (the ICM-20948's 16 g less a margin).
  double saturation = 152.0;  // m/s^2, 15.5 g
  GravityEstimate::Config gravity;
};

}  // namespace dammloam
