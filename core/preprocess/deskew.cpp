#include "core/preprocess/deskew.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/geometry/se3.hpp"

namespace dammloam {
namespace {

// What one firing's points undergo; Move applies it to a point and its normal (if any).
struct RigidMotion {
  Eigen::Isometry3d T;
  void Move(Eigen::Vector3d& p, Eigen::Vector3f* n) const {
    p = T * p;
    if (n) *n = (Eigen::Matrix3d(T.linear()) * n->cast<double>()).cast<float>();
  }
};
struct Turn {
  Eigen::Matrix3d R;
  void Move(Eigen::Vector3d& p, Eigen::Vector3f* n) const {
    p = R * p;
    if (n) *n = (R * n->cast<double>()).cast<float>();
  }
};
// One motion after the other, rounded in between as two passes would be.
struct RigidMotionThenTurn {
  RigidMotion first;
  Turn second;
  void Move(Eigen::Vector3d& p, Eigen::Vector3f* n) const {
    first.Move(p, n);
    second.Move(p, n);
  }
};

// Moves every point (and turns its normal) by the motion of its firing time. Points of one
// firing share a time, so each block reuses its last motion while the time stays.
template <typename MotionAt>
void MoveByFiringTime(ClassifiedScan& scan, const MotionAt& motion_at) {
  Scan& raw = scan.scan;
  const bool has_normals = scan.normals.size() == raw.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, raw.size(), 8192), [&](const auto& range) {
    float last_time = raw.times[range.begin()];
    auto motion = motion_at(last_time);
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (raw.times[i] != last_time) {
        last_time = raw.times[i];
        motion = motion_at(last_time);
      }
      motion.Move(raw.points[i], has_normals ? &scan.normals[i] : nullptr);
    }
  });
}

RigidMotion DeskewMotion(float time, double scan_period, const Vector6d& xi,
                         const Eigen::Isometry3d& T_out_start) {
  return {T_out_start * ExpSE3((time / scan_period) * xi)};
}

Turn AccelerationTurn(float time, double scan_period, double mean_time_sq,
                      const Eigen::Vector3d& angular_acceleration) {
  const double tau = double{time} - 0.5 * scan_period;
  return {ExpSO3(0.5 * (tau * tau - mean_time_sq) * angular_acceleration)};
}

}  // namespace

void DeskewScan(ClassifiedScan& scan, const Eigen::Isometry3d& T_start_end, double scan_period,
                const Eigen::Isometry3d& T_out_start) {
  if (!scan.scan.has_times() || !(scan_period > 0.0)) return;
  // ScaleMotion(T, s) = Exp(s * Log(T)): take the logarithm once, not once per point.
  const Vector6d xi = LogSE3(T_start_end);
  MoveByFiringTime(scan, [&](float time) {
    return DeskewMotion(time, scan_period, xi, T_out_start);
  });
}

void DeskewScanAlong(ClassifiedScan& scan,
                     const std::function<Eigen::Isometry3d(double)>& T_out_point) {
  if (!scan.scan.has_times()) return;
  MoveByFiringTime(scan, [&](float time) { return RigidMotion{T_out_point(double{time})}; });
}

void TurnByAngularAcceleration(ClassifiedScan& scan, const Eigen::Vector3d& angular_acceleration,
                               double scan_period, double mean_time_sq) {
  if (!scan.scan.has_times()) return;
  MoveByFiringTime(scan, [&](float time) {
    return AccelerationTurn(time, scan_period, mean_time_sq, angular_acceleration);
  });
}

void DeskewAndTurn(ClassifiedScan& scan, const Eigen::Isometry3d& T_start_end, double scan_period,
                   const Eigen::Isometry3d& T_out_start,
                   const Eigen::Vector3d& angular_acceleration, double mean_time_sq) {
  if (!scan.scan.has_times()) return;
  if (!(scan_period > 0.0)) {
    TurnByAngularAcceleration(scan, angular_acceleration, scan_period, mean_time_sq);
    return;
  }
  const Vector6d xi = LogSE3(T_start_end);
  MoveByFiringTime(scan, [&](float time) {
    return RigidMotionThenTurn{DeskewMotion(time, scan_period, xi, T_out_start),
                               AccelerationTurn(time, scan_period, mean_time_sq,
                                                angular_acceleration)};
  });
}

}  // namespace dammloam
