#include "tools/simulate/wheel_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "tools/simulate/random_stream.hpp"

namespace dammloam::sim {

BaseTwist TrueBaseTwistAt(const PoseOfTime& chassis, const Eigen::Isometry3d& T_chassis_base, double t) {
  const PoseOfTime base = [&](double u) { return chassis(u) * T_chassis_base; };
  const RigidMotion m = Differentiate(base, t);
  return {m.T_world_body.linear().transpose() * m.velocity_world, m.angular_velocity_body};
}

std::vector<WheelSample> SimulateWheel(const PoseOfTime& chassis, const Eigen::Isometry3d& T_chassis_base,
                                       double clock_zero, double t_begin, double t_end,
                                       const WheelSimOptions& options, std::uint64_t seed,
                                       WheelErrors* drawn) {
  if (!(options.rate_hz > 0.0 && options.rate_hz <= 10000.0)) {
    throw std::invalid_argument("wheel odometry rate must be in (0, 10000] Hz, got " +
                                std::to_string(options.rate_hz));
  }
  RandomStream rng(seed, kWheelStream);
  const bool noisy = !options.noiseless;
  auto scale = [&] {
    const double magnitude = rng.Range(options.scale_error_min, options.scale_error_max);
    return 1.0 + (rng.Uniform() < 0.5 ? -magnitude : magnitude);
  };
  WheelErrors errors;
  if (noisy) {
    errors.speed_scale = scale();
    errors.yaw_rate_scale = scale();
  }
  if (drawn) *drawn = errors;

  const double dt = 1.0 / options.rate_hz;
  std::vector<WheelSample> samples;
  const auto count = static_cast<std::size_t>(std::floor((t_end - t_begin) * options.rate_hz + 1e-9)) + 1;
  for (std::size_t k = 0; t_end >= t_begin && k < count; ++k) {
    const double t = t_begin + static_cast<double>(k) * dt;
    const BaseTwist truth = TrueBaseTwistAt(chassis, T_chassis_base, t);
    WheelSample sample;
    sample.t = clock_zero + t;
    double speed = truth.linear.x(), yaw_rate = truth.angular.z();
    if (noisy) {
      const double lateral_accel = truth.linear.x() * truth.angular.z();
      const double slip = options.slip_yaw_per_lateral_accel * lateral_accel;
      speed = errors.speed_scale * speed + options.speed_noise * rng.Gaussian();
      yaw_rate = errors.yaw_rate_scale * yaw_rate + slip + options.yaw_rate_noise * rng.Gaussian();
    }
    sample.linear_velocity = Eigen::Vector3d(speed, 0.0, 0.0);
    sample.angular_velocity = Eigen::Vector3d(0.0, 0.0, yaw_rate);
    samples.push_back(sample);
  }
  return samples;
}

}  // namespace dammloam::sim
