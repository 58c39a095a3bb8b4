#include "services/dammloamd/imu_input.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

#include "core/inertial/imu_horizon.hpp"
#include "services/dds/inertial_messages.hpp"
#include "services/dds/ros2_messages.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::daemon {
namespace {

// sensor_msgs/Imu: best effort matches every driver's writer; the registration thread takes the
// samples once per scan, so the history holds a few scans of a 100-400 Hz IMU.
dds::TopicQos Ros2ImuQos() { return {false, 200, false}; }

// Samples accepted but not yet handed over are those up to max_clock_offset past a scan; this
// bounds them against a writer that floods the topic.
constexpr std::size_t kMaxPending = 8192;

const char* Explain(const std::string& reason) {
  if (reason == "duplicate_stamp") return "same stamp as the previous sample: dropped";
  if (reason == "out_of_order_stamp") return "stamped before the previous sample: dropped";
  if (reason == "clock_offset") {
    return "more than imu.max_clock_offset from the scan being registered (another clock, or a "
           "wrong imu.time_offset): dropped";
  }
  if (reason == "before_first_scan") return "older than the first scan by more than imu.max_clock_offset: dropped";
  if (reason == "overflow") return "too many samples ahead of the scans: dropped";
  if (reason == "non_finite") return "NaN/inf reading: the scans it falls in are registered with the LiDAR alone";
  if (reason == "saturated") {
    return "a rate at the gyro's full scale (clipped): the scans it falls in are registered with "
           "the LiDAR alone";
  }
  if (reason == "gap") {
    return "first sample after a gap longer than the gyro bridges: the scans across it are "
           "registered with the LiDAR alone";
  }
  return "refused by the odometry";
}

}  // namespace

ImuInput::ImuInput(const dds::Participant& participant, const DaemonConfig& config,
                   DaemonStats& stats)
    : config_(config.imu),
      scan_period_(config.sensor.scan_period),
      stats_(stats),
      stream_(participant, dammloam_msg_Imu_desc, config.topics.imu, dds::ImuQos()) {
  if (config.ros2.enabled) {
    stream_.AddRos2(participant, sensor_msgs_msg_dds__Imu__desc,
                    dds::Ros2TopicName(config.ros2.imu_topic), Ros2ImuQos());
  }
}

void ImuInput::Watch(dds::MiddlewareWatch& watch) const { stream_.Watch(watch); }

void ImuInput::FeedThrough(double t_start, Odometry& odometry, const std::atomic<bool>& stop) {
  first_scan_ = !scan_t_;
  scan_t_ = t_start;
  const double horizon = ImuHorizon(t_start, scan_period_);
  const HorizonWait wait{t_start, scan_period_, horizon, config_.max_wait, first_scan_};
  waited_out_ = stream_.WaitForHorizon(wait, last_t_, stop, [this] { Take(); });
  first_scan_ = false;
  while (!pending_.empty() && pending_.front().t <= horizon) {
    if (!odometry_enabled_) {
      odometry.EnableImu(config_.description);
      odometry_enabled_ = true;
      spdlog::info("IMU: first sample (t {:.6f}, LiDAR clock): the gyro drives the odometry's "
                   "rotation from the scan at {:.6f} on", pending_.front().t, t_start);
    }
    if (!odometry.AddImu(pending_.front())) Fault("refused", true, pending_.front().t);
    pending_.pop_front();
  }
}

void ImuInput::Count(const OdometryResult& result) {
  if (!odometry_enabled_ || !result.gyro) return;
  if (*result.gyro == GyroCoverage::kCovered) {
    stats_.ImuScan();
  } else {
    stats_.ImuScan(waited_out_ ? "wait_timeout" : Name(*result.gyro));
  }
  if (result.accelerometer_used) {
    stats_.AccelerometerScan();
  } else if (result.accelerometer) {
    stats_.AccelerometerScan(Name(*result.accelerometer));
  }
}

void ImuInput::Take() {
  const std::uint64_t taken =
      stream_.TakeAll([this](const dammloam_msg_Imu& m) { Admit(dds::FromImuMessage(m)); },
                      [this](const sensor_msgs_msg_dds__Imu_& m) { Admit(dds::FromRos2Imu(m)); });
  if (taken > 0) stats_.ImuSamples(taken);
}

void ImuInput::Admit(ImuSample sample) {
  sample.t -= config_.description.time_offset;
  const double t = sample.t;
  if (t < *scan_t_ - config_.max_clock_offset ||
      t > *scan_t_ + scan_period_ + config_.max_clock_offset) {
    // Before the first scan the reader may hold a backlog of samples from before the LiDAR
    // started: older ones are that, not a clock fault.
    const bool backlog = first_scan_ && t < *scan_t_;
    return Fault(backlog ? "before_first_scan" : "clock_offset", true, t);
  }
  if (last_t_ && t <= *last_t_) {
    return Fault(t == *last_t_ ? "duplicate_stamp" : "out_of_order_stamp", true, t);
  }
  if (pending_.size() >= kMaxPending) return Fault("overflow", true, t);
  // Kept: the odometry judges each scan's samples (GyroCoverage) and falls back for the scans
  // these fall in; counted here so that Status says which samples were at fault.
  if (!sample.angular_velocity.allFinite() || !sample.linear_acceleration.allFinite()) {
    Fault("non_finite", false, t);
  } else if (sample.angular_velocity.cwiseAbs().maxCoeff() >= integration_.saturation_rate) {
    Fault("saturated", false, t);
  }
  if (last_t_ && t - *last_t_ > integration_.max_gap) Fault("gap", false, t);
  last_t_ = t;
  pending_.push_back(sample);
}

void ImuInput::Fault(const std::string& reason, bool dropped, double t) {
  stats_.ImuSampleFault(reason, dropped);
  // The first few of each reason, then every 1000th: a broken IMU at 200 Hz must not flood the log.
  const std::uint64_t n = ++logged_[reason];
  if (n <= 3 || n % 1000 == 0) {
    spdlog::warn("IMU sample at {:.6f} (LiDAR clock) [{}]: {} ({} so far)", t, reason,
                 Explain(reason), n);
  }
}

}  // namespace dammloam::daemon
