#pragma once
#include <Eigen/Core>

// Gravity in the odometry's world frame (the first scan's sensor frame, not levelled) and the
// accelerometer's bias in the IMU frame, learned from how the registered velocity changed
// against what the accelerometer integrated (issues 52, 55). Between two scans
//   v_k - v_{k-1} = R_{k-1} (increment - B_k bias) + gravity dt,
// with B_k the increment's bias_to_velocity: a least-squares fit over the recent intervals,
// older ones forgotten. While the sensor keeps its heading a bias on a level axis and gravity
// are one constant; turning tells them apart, and the bias's prior keeps it small until then.
// No levelling at rest is needed: the fit starts standing still or moving.
namespace dammloam {

class GravityEstimate {
 public:
  struct Config {
    double warmup = 2.0;          // s of fitted intervals before the estimate is used
    double memory = 30.0;         // s: an interval's weight falls by e over this
    double velocity_sigma = 0.05; // m/s, 1 sigma of one registered velocity change
    double bias_sigma = 0.2;      // m/s^2, 1 sigma of the bias on each axis
  };

  explicit GravityEstimate(const Config& config) : config_(config) {}

  // One interval of duration dt: the registered velocity change (world), the increment's
  // velocity and bias_to_velocity turned into the world frame.
  void Add(const Eigen::Vector3d& registered_change, const Eigen::Vector3d& integrated,
           const Eigen::Matrix3d& bias_to_velocity, double dt);
  bool ready() const { return fitted_time_ >= config_.warmup; }
  const Eigen::Vector3d& gravity() const { return gravity_; }  // world frame, m/s^2
  const Eigen::Vector3d& bias() const { return bias_; }        // IMU frame, m/s^2
  // The velocity change the accelerometer says, world frame.
  Eigen::Vector3d VelocityChange(const Eigen::Vector3d& integrated,
                                 const Eigen::Matrix3d& bias_to_velocity, double dt) const {
    return integrated - bias_to_velocity * bias_ + gravity_ * dt;
  }

 private:
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  Config config_;
  Matrix6 normal_ = Matrix6::Zero();
  Vector6 rhs_ = Vector6::Zero();
  double fitted_time_ = 0.0;
  Eigen::Vector3d gravity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
};

}  // namespace dammloam
