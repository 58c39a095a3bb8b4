#include "tools/odometry/stats_csv.hpp"

#include <iomanip>
#include <stdexcept>

#include "io/process_memory.hpp"

namespace dammloam::tools {

StatsCsv::StatsCsv(const std::filesystem::path& file) : out_(file), file_(file) {
  if (!out_) throw std::runtime_error(file.string() + ": cannot open for writing");
  out_ << "index,stamp,status,projection_ms,normals_ms,classification_ms,deskew_ms,"
          "downsample_ms,registration_ms,map_update_ms,total_ms,alpha,lambda0,lambda1,lambda2,"
          "degenerate0,degenerate1,degenerate2,iterations,converged,correspondences,"
          "n_unknown,n_ground,n_roof,n_wall,n_edge,n_moving,map_points,rss_mib,"
          "searched_points,point_times,tracking,paired_share,innovation,turn_innovation_deg,gyro,set_aside,accelerometer\n";
}

void StatsCsv::Write(const OdometryResult& r) {
  const StageTimings& t = r.timings;
  const DegeneracyReport& d = r.degeneracy;
  out_ << r.scan_index << ',' << std::setprecision(16) << r.stamp << std::setprecision(6) << ','
       << Name(r.status) << ',' << t.projection_ms << ',' << t.normals_ms << ','
       << t.classification_ms << ',' << t.deskew_ms << ',' << t.downsample_ms << ','
       << t.registration_ms << ',' << t.map_update_ms << ',' << t.total_ms << ',' << r.alpha
       << ',' << d.eigenvalues[0] << ',' << d.eigenvalues[1] << ',' << d.eigenvalues[2] << ','
       << d.degenerate[0] << ',' << d.degenerate[1] << ',' << d.degenerate[2] << ','
       << r.iterations << ',' << r.converged << ',' << r.num_correspondences;
  for (auto c : r.class_counts) out_ << ',' << c;
  out_ << ',' << r.map_points << ',' << io::ResidentSetMiB() << ','
       << r.searched_points << ',' << Name(r.point_times) << ',' << Name(r.tracking) << ','
       << r.paired_share << ',' << r.innovation << ',' << r.turn_innovation_deg << ','
       << (r.gyro ? Name(*r.gyro) : "off") << ',' << r.set_aside_points << ','
       << (r.accelerometer_used ? "used" : r.accelerometer ? Name(*r.accelerometer) : "off") << '\n';
  if (!out_) throw std::runtime_error(file_.string() + ": write failed");
}

}  // namespace dammloam::tools
