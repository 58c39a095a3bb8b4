#include "tools/simulate/imu_model.hpp"

#include <cmath>
#include <stdexcept>

#include "tools/simulate/random_stream.hpp"

namespace dammloam::sim {
namespace {

Eigen::Vector3d GaussianVector(RandomStream& rng, double sigma) {
  const double x = rng.Gaussian(), y = rng.Gaussian(), z = rng.Gaussian();
  return sigma * Eigen::Vector3d(x, y, z);
}

Eigen::Vector3d Clip(const Eigen::Vector3d& v, double full_scale) {
  return v.cwiseMax(-full_scale).cwiseMin(full_scale);
}

}  // namespace

ImuTruth TrueImuAt(const PoseOfTime& pose, const Eigen::Isometry3d& T_sensor_imu, double t) {
  const PoseOfTime imu_pose = [&](double u) { return pose(u) * T_sensor_imu; };
  ImuTruth truth;
  truth.imu_motion = Differentiate(imu_pose, t);
  truth.angular_velocity = truth.imu_motion.angular_velocity_body;
  truth.specific_force = truth.imu_motion.T_world_body.linear().transpose() *
                         (truth.imu_motion.acceleration_world - kGravity);
  return truth;
}

std::vector<ImuSample> SimulateImu(const PoseOfTime& pose, double clock_zero, double t_begin,
                                   double t_end, const ImuSimOptions& options, std::uint64_t seed,
                                   ImuBiases* turn_on) {
  if (!(options.rate_hz > 0.0 && options.rate_hz <= 10000.0)) {
    throw std::invalid_argument("IMU rate must be in (0, 10000] Hz, got " + std::to_string(options.rate_hz));
  }
  const double dt = 1.0 / options.rate_hz;
  const ImuNoise& noise = options.description.noise;
  const bool noisy = !options.noiseless;
  // Discrete white noise: sigma = density * sqrt(rate); random walk step: density * sqrt(dt).
  const double gyro_sigma = noise.gyro_noise_density * std::sqrt(options.rate_hz);
  const double accel_sigma = noise.accel_noise_density * std::sqrt(options.rate_hz);
  const double gyro_walk = noise.gyro_bias_random_walk * std::sqrt(dt);
  const double accel_walk = noise.accel_bias_random_walk * std::sqrt(dt);
  RandomStream rng(seed, kImuStream);
  ImuBiases bias;
  if (noisy) {
    bias.gyro = GaussianVector(rng, options.gyro_turn_on_bias);
    bias.accel = GaussianVector(rng, options.accel_turn_on_bias);
  }
  if (turn_on) *turn_on = bias;
  const double offset = noisy ? options.description.time_offset : 0.0;

  std::vector<ImuSample> samples;
  const auto count = static_cast<std::size_t>(std::floor((t_end - t_begin) * options.rate_hz + 1e-9)) + 1;
  samples.reserve(t_end >= t_begin ? count : 0);
  for (std::size_t k = 0; t_end >= t_begin && k < count; ++k) {
    const double t = t_begin + static_cast<double>(k) * dt;
    const ImuTruth truth = TrueImuAt(pose, options.description.T_sensor_imu, t);
    ImuSample sample;
    sample.t = clock_zero + t + offset;
    sample.angular_velocity = truth.angular_velocity;
    sample.linear_acceleration = truth.specific_force;
    if (noisy) {
      sample.angular_velocity += bias.gyro + GaussianVector(rng, gyro_sigma);
      sample.linear_acceleration += bias.accel + GaussianVector(rng, accel_sigma);
      bias.gyro += GaussianVector(rng, gyro_walk);
      bias.accel += GaussianVector(rng, accel_walk);
    }
    sample.angular_velocity = Clip(sample.angular_velocity, options.gyro_full_scale);
    sample.linear_acceleration = Clip(sample.linear_acceleration, options.accel_full_scale);
    samples.push_back(sample);
  }
  return samples;
}

}  // namespace dammloam::sim
