#include "core/preprocess/deskew.hpp"

#include "core/geometry/se3.hpp"

namespace dammloam {

void DeskewScan(ClassifiedScan& scan, const Eigen::Isometry3d& T_start_end, double scan_period) {
  Scan& raw = scan.scan;
  if (!raw.has_times() || !(scan_period > 0.0)) return;
  const bool has_normals = scan.normals.size() == raw.size();
  // ScaleMotion(T, s) = Exp(s * Log(T)): take the logarithm once, not once per point. Points
  // of one firing share a time, so the last pose is reused while the time does not change.
  const Vector6d xi = LogSE3(T_start_end);
  float last_time = raw.times.front();
  Eigen::Isometry3d T = ExpSE3((last_time / scan_period) * xi);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw.times[i] != last_time) {
      last_time = raw.times[i];
      T = ExpSE3((last_time / scan_period) * xi);
    }
    raw.points[i] = T * raw.points[i];
    if (has_normals) scan.normals[i] = (T.linear() * scan.normals[i].cast<double>()).cast<float>();
  }
}

}  // namespace dammloam
