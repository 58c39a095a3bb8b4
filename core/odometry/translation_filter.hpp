#pragma once
#include <Eigen/Core>

namespace dammloam {

// Position and velocity of the sensor in the world frame as a constant-velocity Kalman filter
// whose position measurements are the scan registrations. It answers two questions of full
// mode: how much to trust the predicted position (the prior's information, which grows weak
// along a direction the scans have not seen for a while) and how much of a registration's
// departure from the prediction is a change of speed. Along a direction the scans observe
// well that is all of it, as the plain frame-to-frame velocity; along a weak one only a
// fraction, so the speed is averaged over the scans that saw it.
class TranslationFilter {
 public:
  struct Config {
    // Short-term departure from constant velocity (a walking gait: +-15 % of the speed twice
    // a second): position noise of acceleration * dt^2 per scan, m/s^2.
    double acceleration = 2.0;
    // The gait's departure from constant velocity grows for about half a step, then swings
    // back: past this interval (s) the position noise above stops growing. Scans 0.5 s apart
    // (2 Hz) otherwise gave the prior a 0.5 m sigma, looser than any walk, and in a corridor
    // the registration followed a door recess one stride away (hand-held corridor seed 1 kept
    // at 2 Hz: 21 % of steps tracked; 0.25 and 0.3: 99 %; 0.4: 66 %).
    double gait_time = 0.25;
    // Sustained change of the mean speed (slowing, stopping, setting off), m/s^2: the
    // velocity's random walk. Small, so that a weakly observed axis changes its speed only over
    // several scans: at 0.5 a hand-held VLP-16 walk (seed 2) let the deskew and the velocity
    // feed each other up to 12 m/s (27.6 m APE; 0.43 m at 0.2, seed 1 unchanged at 0.051 m).
    double speed_change = 0.2;
    // Velocity uncertainty at the start and after a reset, and its cap: a carrier's speed
    // varies within this much, however long the scans stay blind (m/s).
    double max_speed_sigma = 1.0;
  };

  explicit TranslationFilter(const Config& config);

  // Velocity unknown (start, time gap).
  void Reset();
  // Covariance of the predicted position after dt seconds; the prior for registration.
  // measured_acceleration_sigma > 0: along the directions `measured` projects onto (world), an
  // accelerometer measured the velocity's change to within that (m/s^2), which there replaces
  // the gait and speed-change noise.
  Eigen::Matrix3d Predict(double dt, double measured_acceleration_sigma = 0.0,
                          const Eigen::Matrix3d& measured = Eigen::Matrix3d::Zero());
  // The velocity after a registration moved the position by `innovation` from the prediction,
  // with `data_information` the scan's own information on the position (without the prior).
  Eigen::Vector3d Update(const Eigen::Vector3d& predicted_velocity,
                         const Eigen::Vector3d& innovation,
                         const Eigen::Matrix3d& data_information);

 private:
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  Config config_;
  Matrix6 P_ = Matrix6::Zero();  // [position; velocity], world frame
};

}  // namespace dammloam
