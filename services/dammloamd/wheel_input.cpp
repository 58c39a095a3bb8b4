#include "services/dammloamd/wheel_input.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

#include "core/inertial/wheel_horizon.hpp"
#include "services/dds/inertial_messages.hpp"
#include "services/dds/ros2_messages.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::daemon {
namespace {

// nav_msgs/Odometry: best effort matches every controller's writer; the registration thread
// takes the samples once per scan, so the history holds a few scans of a 20-100 Hz controller.
dds::TopicQos Ros2WheelQos() { return {false, 100, false}; }

// Samples accepted but not yet handed over are those up to max_clock_offset past a scan; this
// bounds them against a writer that floods the topic.
constexpr std::size_t kMaxPending = 4096;

const char* Explain(const std::string& reason) {
  if (reason == "non_finite") return "NaN/inf stamp or reading: dropped";
  if (reason == "duplicate_stamp") return "same stamp as the previous sample: dropped";
  if (reason == "out_of_order_stamp") return "stamped before the previous sample: dropped";
  if (reason == "absurd_speed") {
    return "speed beyond wheel.max_speed or turn rate beyond wheel.max_yaw_rate (a corrupted "
           "message or a unit error): dropped";
  }
  if (reason == "clock_offset") {
    return "more than wheel.max_clock_offset from the scan being registered (another clock, or a "
           "wrong wheel.time_offset): dropped";
  }
  if (reason == "before_first_scan") {
    return "older than the first scan by more than wheel.max_clock_offset: dropped";
  }
  if (reason == "overflow") return "too many samples ahead of the scans: dropped";
  if (reason == "gap") {
    return "first sample after a silence longer than the wheels bridge: the scans across it are "
           "registered with the LiDAR and its motion model";
  }
  return "refused by the odometry";
}

}  // namespace

WheelInput::WheelInput(const dds::Participant& participant, const DaemonConfig& config,
                       DaemonStats& stats)
    : config_(config.wheel),
      scan_period_(config.sensor.scan_period),
      stats_(stats),
      stream_(participant, dammloam_msg_WheelOdometry_desc, config.topics.wheel_odometry,
              dds::WheelOdometryQos()) {
  use_.T_sensor_base = config_.T_sensor_base;
  use_.max_speed = config_.max_speed;
  use_.max_yaw_rate = config_.max_yaw_rate;
  if (config.ros2.enabled) {
    stream_.AddRos2(participant, nav_msgs_msg_dds__Odometry__desc,
                    dds::Ros2TopicName(config.ros2.wheel_topic), Ros2WheelQos());
  }
}

void WheelInput::Watch(dds::MiddlewareWatch& watch) const { stream_.Watch(watch); }

void WheelInput::FeedThrough(double t_start, Odometry& odometry, const std::atomic<bool>& stop) {
  first_scan_ = !scan_t_;
  scan_t_ = t_start;
  const double horizon = WheelHorizon(t_start, scan_period_);
  const HorizonWait wait{t_start, scan_period_, horizon, config_.max_wait, first_scan_};
  waited_out_ = stream_.WaitForHorizon(wait, last_t_, stop, [this] { Take(); });
  first_scan_ = false;
  while (!pending_.empty() && pending_.front().t <= horizon) {
    if (!odometry_enabled_) {
      odometry.EnableWheel(use_);
      odometry_enabled_ = true;
      spdlog::info("wheel odometry: first sample (t {:.6f}, LiDAR clock): the wheels drive the "
                   "odometry's translation from the scan at {:.6f} on", pending_.front().t, t_start);
    }
    if (!odometry.AddWheel(pending_.front())) Fault("refused", true, pending_.front().t);
    pending_.pop_front();
  }
}

void WheelInput::Count(const OdometryResult& result) {
  // The first scan after the wheels were enabled has no interval (no previous scan): not counted.
  if (!odometry_enabled_ || !result.wheel) return;
  if (*result.wheel == WheelCoverage::kCovered) {
    stats_.WheelScan();
  } else {
    stats_.WheelScan(waited_out_ ? "wait_timeout" : Name(*result.wheel));
  }
}

void WheelInput::Take() {
  const std::uint64_t taken = stream_.TakeAll(
      [this](const dammloam_msg_WheelOdometry& m) { Admit(dds::FromWheelMessage(m)); },
      [this](const nav_msgs_msg_dds__Odometry_& m) {
        Admit(dds::FromRos2WheelOdometry(m));
      });
  if (taken > 0) stats_.WheelSamples(taken);
}

// The checks of Odometry::AddWheel, in its order, made here so that Status names each fault;
// the offline runner hands the same samples to AddWheel, which refuses the same ones.
void WheelInput::Admit(WheelSample sample) {
  sample.t -= config_.time_offset;
  const double t = sample.t;
  if (!std::isfinite(t) || !sample.linear_velocity.allFinite() ||
      !sample.angular_velocity.allFinite()) {
    return Fault("non_finite", true, t);
  }
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
  if (!(sample.linear_velocity.norm() <= use_.max_speed) ||
      !(sample.angular_velocity.cwiseAbs().maxCoeff() <= use_.max_yaw_rate)) {
    return Fault("absurd_speed", true, t);
  }
  if (pending_.size() >= kMaxPending) return Fault("overflow", true, t);
  // Kept: the odometry judges each interval's samples (WheelCoverage) and falls back for the
  // scans across the silence; counted here so that Status says where it was.
  if (last_t_ && t - *last_t_ > use_.integration.max_gap) Fault("gap", false, t);
  last_t_ = t;
  pending_.push_back(sample);
}

void WheelInput::Fault(const std::string& reason, bool dropped, double t) {
  stats_.WheelSampleFault(reason, dropped);
  // The first few of each reason, then every 1000th: broken wheels at 50 Hz must not flood the log.
  const std::uint64_t n = ++logged_[reason];
  if (n <= 3 || n % 1000 == 0) {
    spdlog::warn("wheel sample at {:.6f} (LiDAR clock) [{}]: {} ({} so far)", t, reason,
                 Explain(reason), n);
  }
}

}  // namespace dammloam::daemon
