#pragma once
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "core/inertial/imu_sample.hpp"
#include "core/inertial/wheel_sample.hpp"
#include "tools/simulate/imu_model.hpp"
#include "tools/simulate/wheel_model.hpp"

// The IMU and wheel streams written beside a simulated run's scans (imu.csv, wheel.csv), each
// from its own random stream of the run's seed: the scans and the ground truth are the same
// bit for bit with or without them.
namespace dammloam::sim {

class Simulator;

struct InertialStreamOptions {
  bool no_imu = false;    // no imu.csv
  bool no_wheel = false;  // no wheel.csv (only the wheeled and vehicle carriers have one)
  ImuSimOptions imu;
  WheelSimOptions wheel;
};

struct InertialStreams {
  std::optional<std::vector<ImuSample>> imu;
  ImuSimOptions imu_options;
  ImuBiases imu_turn_on;
  std::optional<std::vector<WheelSample>> wheel;
  Eigen::Isometry3d T_sensor_base = Eigen::Isometry3d::Identity();  // nominal, no vibration
  WheelErrors wheel_errors;
};

// Streams over [first scan start, last scan end] of `scans` scans of `simulator`'s run.
InertialStreams SimulateInertialStreams(const Simulator& simulator, int scans,
                                        const InertialStreamOptions& options);

// The base frame of a wheeled carrier: on the ground right under the sensor, sensor axes.
Eigen::Isometry3d SensorToBase(const Simulator& simulator);

// "imu.csv: 35001 samples at 100 Hz over 350.0 s ...; wheel.csv: ..." for the log.
std::string StreamsSummary(const InertialStreams& streams);

}  // namespace dammloam::sim
