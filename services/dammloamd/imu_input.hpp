#pragma once
// dammloamd's IMU input (issue 55), used on the registration thread only: takes the Imu samples
// (the native topic and, with ros2, sensor_msgs/Imu), checks each one, and before each scan
// hands the odometry every sample up to the scan's horizon (core/inertial/imu_horizon.hpp), as
// dammloam-odometry's ImuFeed does with a sequence's imu.csv: lock-step over DDS and the offline
// runner then register with the same samples.
//
// Faults never stop the odometry. A sample that cannot be placed on the timeline (a duplicate or
// out-of-order stamp, a stamp too far from the scans: another clock) is dropped; a sample that
// can (NaN/inf or clipped rates, one after a gap) is handed over, and the odometry registers the
// scans it falls in with the LiDAR alone. Each is counted in Status (DaemonStatus.imu_*).
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include "core/inertial/gyro_integration.hpp"
#include "core/odometry/odometry.hpp"
#include "dammloam.h"
#include "sensor_msgs.h"
#include "services/dammloamd/daemon_config.hpp"
#include "services/dammloamd/daemon_stats.hpp"
#include "services/dammloamd/sample_stream.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/middleware_watch.hpp"

namespace dammloam::daemon {

class ImuInput {
 public:
  ImuInput(const dds::Participant& participant, const DaemonConfig& config, DaemonStats& stats);

  // Before registering the scan starting at t_start (LiDAR clock): takes what arrived, waits
  // (at most imu.max_wait, and only while an IMU writer is matched) until a sample at or past
  // the scan's horizon arrived, and hands `odometry` every sample up to the horizon. The first
  // sample handed over enables the odometry's gyro: until then the odometry is the LiDAR's alone.
  void FeedThrough(double t_start, Odometry& odometry, const std::atomic<bool>& stop);
  // After the scan: whether the gyro covered it, or why not (counted once samples have arrived).
  void Count(const OdometryResult& result);
  void Watch(dds::MiddlewareWatch& watch) const;

 private:
  void Take();
  void Admit(ImuSample sample);  // stamp as sent (IMU clock)
  void Fault(const std::string& reason, bool dropped, double t);

  ImuConfig config_;
  double scan_period_;
  GyroIntegrationConfig integration_;  // max_gap and saturation_rate, as the odometry judges
  DaemonStats& stats_;
  SampleStream<dammloam_msg_Imu, sensor_msgs_msg_dds__Imu_> stream_;
  std::deque<ImuSample> pending_;   // accepted, LiDAR clock, in stamp order, not handed over yet
  std::optional<double> last_t_;    // the newest accepted stamp
  std::optional<double> scan_t_;    // start of the scan being fed; none before the first scan
  bool odometry_enabled_ = false;
  bool waited_out_ = false;         // this scan's samples had not all come within max_wait
  bool first_scan_ = false;         // feeding the first scan (older samples: from before it)
  std::map<std::string, std::uint64_t> logged_;  // faults per reason, to thin out the log
};

}  // namespace dammloam::daemon
