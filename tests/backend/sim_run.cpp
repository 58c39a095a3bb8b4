#include "tests/backend/sim_run.hpp"

#include <cmath>

namespace dammloam::test {

sim::SensorSpec TestSensor() {
  sim::SensorSpec spec = sim::Os1_64();
  spec.name = "test-32";
  spec.columns = 512;
  spec.vertical_angles_deg = sim::UniformVerticalAngles(32, 22.5, -22.5);
  return spec;
}

std::vector<Eigen::Vector3d> DeskewedScan(const sim::Simulator& simulator, int index) {
  const Scan scan = simulator.SimulateScan(index);
  const Eigen::Isometry3d T_start_inv = simulator.PoseAt(scan.t_start).inverse();
  std::vector<Eigen::Vector3d> points;
  points.reserve(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double t = scan.t_start + (scan.has_times() ? scan.times[i] : 0.0f);
    points.push_back(T_start_inv * simulator.PoseAt(t) * scan.points[i]);
  }
  return points;
}

// The front end reports covariances of a left (world-frame) perturbation: a body-frame one seen
// through the pose's adjoint [R, [t]x R; 0, R].
Matrix6d WorldCovariance(const Matrix6d& body, const Eigen::Isometry3d& T_world_body) {
  Matrix6d adjoint = Matrix6d::Zero();
  const Eigen::Matrix3d R = T_world_body.rotation();
  adjoint.topLeftCorner<3, 3>() = R;
  adjoint.topRightCorner<3, 3>() = Hat(T_world_body.translation()) * R;
  adjoint.bottomRightCorner<3, 3>() = R;
  return adjoint * body * adjoint.transpose();
}

SimRun MakeSimRun(const sim::Simulator& simulator, int count, int stride,
                  const DriftModel& drift) {
  SimRun run;
  Eigen::Isometry3d odom = Eigen::Isometry3d::Identity();
  for (int k = 0; k < count; ++k) {
    const int index = k * stride;
    const Eigen::Isometry3d truth = simulator.PoseAt(simulator.ScanStartTime(index));
    if (k == 0) {
      odom = truth;
    } else {
      Eigen::Isometry3d step = run.truth.back().inverse() * truth;
      const double metres = step.translation().norm();
      step.translation() *= 1.0 + drift.scale_error;
      const Eigen::Vector3d up = run.truth.back().rotation().transpose() * Eigen::Vector3d::UnitZ();
      step.translation() -= drift.climb_loss * up.dot(step.translation()) * up;
      step.linear() = Eigen::AngleAxisd(drift.yaw_per_metre * metres, Eigen::Vector3d::UnitZ())
                          .toRotationMatrix() * step.linear();
      odom = odom * step;
    }
    OdometryResult r;
    r.stamp = simulator.ScanStartTime(index);
    r.scan_index = static_cast<std::uint64_t>(index);
    r.T_world_sensor = odom;
    Vector6d sigma;
    sigma << Eigen::Vector3d::Constant(drift.translation_sigma),
        Eigen::Vector3d::Constant(drift.rotation_sigma);
    r.covariance = WorldCovariance(sigma.cwiseAbs2().asDiagonal(), odom);
    r.deskewed_points = DeskewedScan(simulator, index);
    r.labels.assign(r.deskewed_points.size(), PointClass::Unknown);
    run.odometry.push_back(std::move(r));
    run.truth.push_back(truth);
  }
  return run;
}

double PositionRmse(const std::vector<Eigen::Isometry3d>& estimate,
                    const std::vector<Eigen::Isometry3d>& truth) {
  double sum = 0.0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    sum += (estimate[i].translation() - truth[i].translation()).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(estimate.size()));
}

}  // namespace dammloam::test
