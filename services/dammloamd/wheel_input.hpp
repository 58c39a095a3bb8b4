#pragma once
// dammloamd's wheel-odometry input (issue 55), used on the registration thread only: takes the
// WheelOdometry samples (the native topic and, with ros2, nav_msgs/Odometry's twist), checks each
// one, and before each scan hands the odometry every sample up to the scan's horizon
// (core/inertial/wheel_horizon.hpp), as dammloam-odometry's WheelFeed does with a sequence's
// wheel.csv: lock-step over DDS and the offline runner then register with the same samples. The
// IMU's input (imu_input.hpp) is the same pattern for the gyro.
//
// Faults never stop the odometry. A sample the estimator cannot use (a NaN or infinite value, a
// duplicate or out-of-order stamp, an absurd speed, a stamp too far from the scans: another
// clock) is dropped; the first sample after a silence longer than the wheels bridge is kept, and
// the odometry registers the scans across the silence with the LiDAR and its motion model. Each
// is counted in Status (DaemonStatus.wheel_*).
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include "core/inertial/wheel_use_config.hpp"
#include "core/odometry/odometry.hpp"
#include "dammloam.h"
#include "nav_msgs.h"
#include "services/dammloamd/daemon_config.hpp"
#include "services/dammloamd/daemon_stats.hpp"
#include "services/dammloamd/sample_stream.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/middleware_watch.hpp"

namespace dammloam::daemon {

class WheelInput {
 public:
  WheelInput(const dds::Participant& participant, const DaemonConfig& config, DaemonStats& stats);

  // Before registering the scan starting at t_start (LiDAR clock): takes what arrived, waits
  // (at most wheel.max_wait, and only while a wheel writer is matched) until a sample at or past
  // the scan's horizon arrived, and hands `odometry` every sample up to the horizon. The first
  // sample handed over enables the odometry's wheels: until then the odometry is the LiDAR's.
  void FeedThrough(double t_start, Odometry& odometry, const std::atomic<bool>& stop);
  // After the scan: whether the wheels covered its interval, or why not (counted once samples
  // have arrived).
  void Count(const OdometryResult& result);
  void Watch(dds::MiddlewareWatch& watch) const;

 private:
  void Take();
  void Admit(WheelSample sample);  // stamp as sent (the wheel controller's clock)
  void Fault(const std::string& reason, bool dropped, double t);

  WheelConfig config_;
  WheelUseConfig use_;  // what the odometry is enabled with: the offline runner's but the extrinsic
  double scan_period_;
  DaemonStats& stats_;
  SampleStream<dammloam_msg_WheelOdometry, nav_msgs_msg_dds__Odometry_> stream_;
  std::deque<WheelSample> pending_;  // accepted, LiDAR clock, in stamp order, not handed over yet
  std::optional<double> last_t_;     // the newest accepted stamp
  std::optional<double> scan_t_;     // start of the scan being fed; none before the first scan
  bool odometry_enabled_ = false;
  bool waited_out_ = false;          // this scan's samples had not all come within max_wait
  bool first_scan_ = false;          // feeding the first scan (older samples: from before it)
  std::map<std::string, std::uint64_t> logged_;  // faults per reason, to thin out the log
};

}  // namespace dammloam::daemon
