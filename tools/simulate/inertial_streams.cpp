#include "tools/simulate/inertial_streams.hpp"

#include <cstdio>

#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {

Eigen::Isometry3d SensorToBase(const Simulator& simulator) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.0, 0.0, -simulator.trajectory().spec().sensor_height);
  return T;
}

InertialStreams SimulateInertialStreams(const Simulator& simulator, int scans,
                                        const InertialStreamOptions& options) {
  InertialStreams out;
  out.imu_options = options.imu;
  const Trajectory& trajectory = simulator.trajectory();
  const double clock_zero = simulator.options().t0;
  const std::uint64_t seed = simulator.options().seed;
  const double end = std::max(scans, 0) * simulator.sensor().scan_period;
  if (!options.no_imu) {
    const PoseOfTime pose = [&](double t) { return trajectory.Pose(t); };
    out.imu = SimulateImu(pose, clock_zero, 0.0, end, options.imu, seed, &out.imu_turn_on);
  }
  const bool wheeled = simulator.motion() == MotionKind::Wheeled || simulator.motion() == MotionKind::Vehicle;
  out.T_sensor_base = SensorToBase(simulator);
  if (wheeled && !options.no_wheel) {
    const PoseOfTime chassis = [&](double t) { return trajectory.ChassisPose(t); };
    out.wheel = SimulateWheel(chassis, out.T_sensor_base, clock_zero, 0.0, end, options.wheel, seed,
                              &out.wheel_errors);
  }
  return out;
}

std::string StreamsSummary(const InertialStreams& streams) {
  char text[512];
  std::string out;
  if (streams.imu && !streams.imu->empty()) {
    const ImuBiases& b = streams.imu_turn_on;
    std::snprintf(text, sizeof text,
                  "imu.csv: %zu samples at %.0f Hz, clock offset %.4f s, turn-on bias gyro "
                  "%.4f %.4f %.4f rad/s accel %.4f %.4f %.4f m/s^2",
                  streams.imu->size(), streams.imu_options.rate_hz, streams.imu_options.description.time_offset,
                  b.gyro.x(), b.gyro.y(), b.gyro.z(), b.accel.x(), b.accel.y(), b.accel.z());
    out += text;
  } else {
    out += "imu.csv: not written";
  }
  if (streams.wheel && !streams.wheel->empty()) {
    std::snprintf(text, sizeof text, "; wheel.csv: %zu samples, speed scale %.4f, yaw-rate scale %.4f",
                  streams.wheel->size(), streams.wheel_errors.speed_scale, streams.wheel_errors.yaw_rate_scale);
    out += text;
  } else {
    out += "; wheel.csv: not written";
  }
  return out;
}

}  // namespace dammloam::sim
