#pragma once
#include <Eigen/Core>

// Gravity in the odometry's world frame (the first scan's sensor frame, not levelled) and the
// accelerometer's bias in the IMU frame (issues 52, 55), as a Kalman filter over how the
// registered velocity changed against what the accelerometer integrated. Between two scans
//   v_k - v_{k-1} = R_{k-1} (increment - B_k bias) + gravity dt,
// with B_k the increment's bias_to_velocity. It starts from the mean specific force over the
// first `warmup` seconds (gravity's direction, its known magnitude), standing or moving, and
// learns as much along each direction as the registrations measured there: along one they do not
// observe (a featureless corridor's axis) the registered velocity is the prediction's own, and
// gravity keeps its start value and uncertainty there, and Trusted() leaves it out.
namespace dammloam {

class GravityEstimate {
 public:
  struct Config {
    double warmup = 1.0;             // s of specific force averaged for the first gravity
    double initial_sigma = 0.5;      // m/s^2, that first gravity's 1 sigma per axis (a walk's
                                     //   acceleration over the warmup, the bias)
    double bias_sigma = 0.2;         // m/s^2, 1 sigma of the bias per axis at the start
    double velocity_sigma = 0.02;    // m/s, 1 sigma of one registered velocity change
    double gravity_walk = 0.002;     // m/s^2/sqrt(s): the odometry's tilt drifts, gravity with it
    double bias_walk = 4e-4;         // m/s^3/sqrt(Hz), the bias's random walk
    double trusted_sigma = 0.05;     // m/s^2: directions known better than this are trusted
  };

  explicit GravityEstimate(const Config& config) : config_(config) {}

  // One interval of duration dt: the registered velocity change (world), the increment's
  // velocity and bias_to_velocity turned into the world frame, and how well the scans measured
  // that change beyond velocity_sigma (world, m^2/s^2; huge along a direction they did not
  // observe).
  void Add(const Eigen::Vector3d& registered_change, const Eigen::Vector3d& integrated,
           const Eigen::Matrix3d& bias_to_velocity, double dt,
           const Eigen::Matrix3d& change_covariance = Eigen::Matrix3d::Zero());
  bool ready() const { return initialised_; }
  const Eigen::Vector3d& gravity() const { return gravity_; }  // world frame, m/s^2
  const Eigen::Vector3d& bias() const { return bias_; }        // IMU frame, m/s^2
  // The velocity change the accelerometer says, world frame.
  Eigen::Vector3d VelocityChange(const Eigen::Vector3d& integrated,
                                 const Eigen::Matrix3d& bias_to_velocity, double dt) const {
    return integrated - bias_to_velocity * bias_ + gravity_ * dt;
  }
  // Projector (world) onto the directions along which the acceleration error over an interval
  // with this bias_to_velocity is below trusted_sigma.
  Eigen::Matrix3d Trusted(const Eigen::Matrix3d& bias_to_velocity, double dt) const;

 private:
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  void Initialise();
  Config config_;
  bool initialised_ = false;
  Eigen::Vector3d force_sum_ = Eigen::Vector3d::Zero();  // of integrated, over the warmup
  double force_time_ = 0.0;
  Eigen::Vector3d gravity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  Matrix6 P_ = Matrix6::Zero();
};

}  // namespace dammloam
