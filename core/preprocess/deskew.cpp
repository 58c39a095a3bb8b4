#include "core/preprocess/deskew.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/geometry/se3.hpp"

namespace dammloam {

void DeskewScan(ClassifiedScan& scan, const Eigen::Isometry3d& T_start_end, double scan_period,
                const Eigen::Isometry3d& T_out_start) {
  Scan& raw = scan.scan;
  if (!raw.has_times() || !(scan_period > 0.0)) return;
  const bool has_normals = scan.normals.size() == raw.size();
  // ScaleMotion(T, s) = Exp(s * Log(T)): take the logarithm once, not once per point. Points
  // of one firing share a time, so each block reuses its last pose while the time stays.
  const Vector6d xi = LogSE3(T_start_end);
  const auto pose_at = [&](float time) {
    return T_out_start * ExpSE3((time / scan_period) * xi);
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, raw.size(), 8192), [&](const auto& range) {
    float last_time = raw.times[range.begin()];
    Eigen::Isometry3d T = pose_at(last_time);
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (raw.times[i] != last_time) {
        last_time = raw.times[i];
        T = pose_at(last_time);
      }
      raw.points[i] = T * raw.points[i];
      if (has_normals) {
        scan.normals[i] = (T.linear() * scan.normals[i].cast<double>()).cast<float>();
      }
    }
  });
}

}  // namespace dammloam
