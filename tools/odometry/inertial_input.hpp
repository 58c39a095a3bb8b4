#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "core/inertial/imu_sample.hpp"
#include "core/inertial/inertial_config.hpp"
#include "core/inertial/wheel_sample.hpp"
#include "core/odometry/odometry.hpp"
#include "tools/odometry/runner.hpp"

// A sequence's imu.csv and wheel.csv with their meta.json extrinsics, read once before the run
// (issue 55). The odometry uses the IMU's gyroscope (Odometry::EnableImu) and the wheel odometry
// (Odometry::EnableWheel). Without them (or with --no-imu / --no-wheel) the poses stay
// bit-identical to the LiDAR's alone.
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

// Hands the IMU samples to the odometry scan by scan, as a live stream would have them (up to
// just past the end of the scan about to be registered), and counts how each scan used the
// gyro. Without IMU samples it does nothing, and the odometry is the LiDAR's alone.
class ImuFeed {
 public:
  ImuFeed(const InertialInput& input, Odometry& odometry);
  // Every sample stamped up to t (plus two sample periods, to interpolate at t).
  void Through(double t);
  void Count(const OdometryResult& result);
  // One line: whether the IMU was used, on how many scans, how many fell back and why, the
  // estimated gyro bias.
  void Log() const;

 private:
  const std::vector<ImuSample>* samples_ = nullptr;
  Odometry& odometry_;
  std::size_t next_ = 0;
  std::size_t scans_ = 0;
  std::array<std::size_t, 8> by_coverage_{};  // indexed by GyroCoverage
  std::size_t accelerometer_used_ = 0;
};

// Hands the wheel samples to the odometry scan by scan, as ImuFeed does the IMU's, and counts
// how each scan interval used them. Without wheel samples it does nothing.
class WheelFeed {
 public:
  WheelFeed(const InertialInput& input, Odometry& odometry);
  void Through(double t);
  void Count(const OdometryResult& result);
  // One line: on how many scan intervals the wheels were used, how many fell back and why,
  // how many samples the odometry refused and why.
  void Log() const;

 private:
  const std::vector<WheelSample>* samples_ = nullptr;
  Odometry& odometry_;
  std::size_t next_ = 0;
  std::size_t scans_ = 0;
  std::array<std::size_t, 4> by_coverage_{};  // indexed by WheelCoverage
};

}  // namespace dammloam::tools
