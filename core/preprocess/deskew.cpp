#include "core/preprocess/deskew.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/geometry/se3.hpp"

namespace dammloam {
namespace {

Eigen::Matrix3d RotationOf(const Eigen::Isometry3d& T) { return T.linear(); }
const Eigen::Matrix3d& RotationOf(const Eigen::Matrix3d& R) { return R; }

// Moves every point (and turns its normal) by the pose (or rotation) of its firing time. Points
// of one firing share a time, so each block reuses its last pose while the time stays.
template <typename PoseAt>
void MoveByFiringTime(ClassifiedScan& scan, const PoseAt& pose_at) {
  Scan& raw = scan.scan;
  const bool has_normals = scan.normals.size() == raw.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, raw.size(), 8192), [&](const auto& range) {
    float last_time = raw.times[range.begin()];
    auto T = pose_at(last_time);
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (raw.times[i] != last_time) {
        last_time = raw.times[i];
        T = pose_at(last_time);
      }
      raw.points[i] = T * raw.points[i];
      if (has_normals) {
        scan.normals[i] = (RotationOf(T) * scan.normals[i].template cast<double>()).template cast<float>();
      }
    }
  });
}

}  // namespace

void DeskewScan(ClassifiedScan& scan, const Eigen::Isometry3d& T_start_end, double scan_period,
                const Eigen::Isometry3d& T_out_start) {
  if (!scan.scan.has_times() || !(scan_period > 0.0)) return;
  // ScaleMotion(T, s) = Exp(s * Log(T)): take the logarithm once, not once per point.
  const Vector6d xi = LogSE3(T_start_end);
  MoveByFiringTime(scan, [&](float time) {
    return Eigen::Isometry3d(T_out_start * ExpSE3((time / scan_period) * xi));
  });
}

void TurnByAngularAcceleration(ClassifiedScan& scan, const Eigen::Vector3d& angular_acceleration,
                               double scan_period, double mean_time_sq) {
  if (!scan.scan.has_times()) return;
  MoveByFiringTime(scan, [&](float time) {
    const double tau = double{time} - 0.5 * scan_period;
    return ExpSO3(0.5 * (tau * tau - mean_time_sq) * angular_acceleration);
  });
}

}  // namespace dammloam
