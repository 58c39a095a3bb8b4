#pragma once
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "core/inertial/imu_sample.hpp"
#include "core/inertial/inertial_config.hpp"
#include "core/inertial/wheel_sample.hpp"
#include "tools/odometry/runner.hpp"

// A sequence's imu.csv and wheel.csv with their meta.json extrinsics, read once before the run
// (issue 55). The estimator does not use them yet: this is the one place it will take them
// from, so that without them (or with --no-imu / --no-wheel) the poses stay bit-identical.
namespace dammloam::tools {

struct InertialInput {
  std::optional<std::vector<ImuSample>> imu;  // stamps on the LiDAR clock (time offset removed)
  ImuDescription imu_description;             // meta.json's, else the OS1 defaults
  std::optional<std::vector<WheelSample>> wheel;
  Eigen::Isometry3d T_sensor_base = Eigen::Isometry3d::Identity();
};

// Nothing for bags and KITTI folders without the files. Malformed files: io::IoError; dropped
// samples are counted and logged with their reason (unless quiet).
InertialInput ReadInertialInput(const RunnerOptions& options);

}  // namespace dammloam::tools
