#pragma once
#include <Eigen/Geometry>
#include <vector>

#include "core/odometry/odometry_result.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::test {

// Drift injected into the "odometry" fed to the back-end (so the back-end tests do not depend on
// the front end): per metre travelled, a yaw error and a scale error.
struct DriftModel {
  double yaw_per_metre = 0.004;  // rad/m
  double scale_error = 0.01;     // fraction of each step
  // Fraction of each step's height change lost on top of scale_error (a hand-held front end
  // climbing stairs: VLP-16 on two-floor kept 2.1 of the 3 m).
  double climb_loss = 0.0;
  // Standard deviations of each step's reported covariance (body frame).
  double translation_sigma = 0.01;  // metres
  double rotation_sigma = 0.01;     // radians
};

struct SimRun {
  std::vector<OdometryResult> odometry;     // drifted poses, ground-truth-deskewed clouds
  std::vector<Eigen::Isometry3d> truth;     // T_world_sensor at each scan start
};

// A body-frame pose covariance [t; r] as the front end reports it: of a left (world-frame)
// perturbation of T_world_body.
Matrix6d WorldCovariance(const Matrix6d& body, const Eigen::Isometry3d& T_world_body);

// A cheap sensor for tests: 32 rings over +-22.5 deg, 512 columns.
sim::SensorSpec TestSensor();

// Every `stride`-th scan of the simulator for `count` scans, deskewed with the true motion.
SimRun MakeSimRun(const sim::Simulator& simulator, int count, int stride, const DriftModel& drift);

// Deskewed scan `index` in the sensor frame at scan start (true motion used for deskewing).
std::vector<Eigen::Vector3d> DeskewedScan(const sim::Simulator& simulator, int index);

double PositionRmse(const std::vector<Eigen::Isometry3d>& estimate,
                    const std::vector<Eigen::Isometry3d>& truth);

}  // namespace dammloam::test
