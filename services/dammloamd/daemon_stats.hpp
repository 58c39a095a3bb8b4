#pragma once
// Counters and latency window behind the Status topic; every daemon thread reports here.
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <string_view>

#include "services/dds/middleware_watch.hpp"

namespace dammloam::daemon {

// The stages whose caught exceptions are counted apart (DaemonStatus.*_errors).
enum class Stage { kReceive, kPublish, kBackend };
const char* Name(Stage stage);

// Test seam: called where each stage's guarded work starts (receive: per sample, publish: per
// pose, backend: per pass); a test throws from it to see the failure reported. Empty otherwise.
using FaultInjector = std::function<void(Stage)>;

struct StatusSnapshot {
  std::uint64_t received = 0, processed = 0, dropped = 0, rejected = 0, errors = 0;
  std::map<std::string, std::uint64_t> by_reason;  // "rejected:<code>" and "dropped:<where>"
  std::uint64_t commands_refused = 0;
  std::map<std::string, std::uint64_t> refused_by_reason;
  std::uint64_t receive_errors = 0, publish_errors = 0, backend_errors = 0;
  // What DDS dropped (dds::DropKind); incompatible_qos = requested + offered.
  std::uint64_t samples_lost = 0, samples_rejected = 0, samples_undeserializable = 0,
                incompatible_qos = 0;
  std::map<std::string, std::uint64_t> middleware_by_reason;  // dds::MiddlewareEvent::Reason()
  // Tracking health (Odometry.tracking) and scans whose point times could not drive a deskew.
  std::string tracking = "tracking";  // the newest scan's
  std::uint64_t degraded = 0, lost = 0, without_point_times = 0;
  // The IMU input (DaemonStatus.imu_*): samples taken and dropped, scans with and without the
  // gyro, per "sample:<fault>" and "scan:<why>".
  std::uint64_t imu_samples = 0, imu_samples_dropped = 0, scans_with_imu = 0,
                scans_without_imu = 0;
  std::map<std::string, std::uint64_t> imu_by_reason;
  // The wheel-odometry input (DaemonStatus.wheel_*), the same counts for the wheels.
  std::uint64_t wheel_samples = 0, wheel_samples_dropped = 0, scans_with_wheel = 0,
                scans_without_wheel = 0;
  std::map<std::string, std::uint64_t> wheel_by_reason;
  // The accelerometer (DaemonStatus.*accelerometer*): scans whose prior it drove, the others
  // per "scan:<why>".
  std::uint64_t scans_with_accelerometer = 0, scans_without_accelerometer = 0;
  std::map<std::string, std::uint64_t> accelerometer_by_reason;
  std::uint64_t labelled_clouds_published = 0, labelled_clouds_skipped = 0;
  double latency_median_ms = 0, latency_p95_ms = 0, latency_p99_ms = 0, latency_max_ms = 0;
  std::string last_error;
  double last_error_wall_time = 0.0;  // seconds since the epoch
};

class DaemonStats {
 public:
  void Received();
  // A published pose; `tracking` and `point_times` are its Name()s.
  void Processed(double latency_ms, std::string_view tracking = "tracking",
                 std::string_view point_times = "usable");
  void Dropped(const std::string& where);
  // A labelled cloud written, or skipped because the labelled-cloud thread fell behind.
  void LabelledCloud(bool published);
  void Rejected(const std::string& code, const std::string& message);
  // An error that is not about a scan (a failed command): counted and shown as last_error.
  void Error(const std::string& message);
  // A Command refused before it ran (an error too).
  void CommandRefused(const std::string& reason, const std::string& message);
  // An exception caught in a stage (an error too).
  void StageFailed(Stage stage, const std::string& message);
  // Something DDS dropped (an error too, last_error = event.Describe()).
  void MiddlewareDropped(const dds::MiddlewareEvent& event);
  // IMU samples taken from the topics.
  void ImuSamples(std::uint64_t taken);
  // A sample fault (reason without the "sample:" prefix); `dropped`: not handed to the estimator.
  void ImuSampleFault(const std::string& reason, bool dropped);
  // A scan registered with the gyro (why empty) or without it (why: the reason).
  void ImuScan(std::string_view why = {});
  // The same for wheel odometry: samples taken, a sample fault, a scan with or without them.
  void WheelSamples(std::uint64_t taken);
  void WheelSampleFault(const std::string& reason, bool dropped);
  void WheelScan(std::string_view why = {});
  // A scan whose motion prior the accelerometer drove (why empty), or why it did not.
  void AccelerometerScan(std::string_view why = {});
  StatusSnapshot Snapshot() const;

 private:
  // One scan with an input (why empty) or without it for `why` ("scan:<why>" in by_reason).
  static void CountScan(std::string_view why, std::uint64_t& with, std::uint64_t& without,
                        std::map<std::string, std::uint64_t>& by_reason);
  void NoteError(const std::string& message);  // mutex_ held

  static constexpr std::size_t kLatencyWindow = 100;
  mutable std::mutex mutex_;
  StatusSnapshot counters_;
  std::deque<double> latencies_ms_;
};

}  // namespace dammloam::daemon
