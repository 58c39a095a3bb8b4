#include "services/dammloamd/daemon_stats.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

namespace dammloam::daemon {
namespace {

double Percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const auto index = static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5);
  return sorted[std::min(index, sorted.size() - 1)];
}

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

const char* Name(Stage stage) {
  switch (stage) {
    case Stage::kReceive: return "receive";
    case Stage::kPublish: return "publish";
    case Stage::kBackend: return "backend";
  }
  return "?";
}

void DaemonStats::Received() {
  std::lock_guard lock(mutex_);
  ++counters_.received;
}

void DaemonStats::Processed(double latency_ms, std::string_view tracking,
                            std::string_view point_times) {
  std::lock_guard lock(mutex_);
  ++counters_.processed;
  counters_.tracking = tracking;
  counters_.degraded += tracking == "degraded";
  counters_.lost += tracking == "lost";
  counters_.without_point_times += point_times != "usable" && point_times != "absent";
  latencies_ms_.push_back(latency_ms);
  if (latencies_ms_.size() > kLatencyWindow) latencies_ms_.pop_front();
}

void DaemonStats::ImuSamples(std::uint64_t taken) {
  std::lock_guard lock(mutex_);
  counters_.imu_samples += taken;
}

void DaemonStats::ImuSampleFault(const std::string& reason, bool dropped) {
  std::lock_guard lock(mutex_);
  counters_.imu_samples_dropped += dropped;
  ++counters_.imu_by_reason["sample:" + reason];
}

void DaemonStats::CountScan(std::string_view why, std::uint64_t& with, std::uint64_t& without,
                            std::map<std::string, std::uint64_t>& by_reason) {
  if (why.empty()) {
    ++with;
    return;
  }
  ++without;
  ++by_reason["scan:" + std::string(why)];
}

void DaemonStats::ImuScan(std::string_view why) {
  std::lock_guard lock(mutex_);
  CountScan(why, counters_.scans_with_imu, counters_.scans_without_imu, counters_.imu_by_reason);
}

void DaemonStats::AccelerometerScan(std::string_view why) {
  std::lock_guard lock(mutex_);
  CountScan(why, counters_.scans_with_accelerometer, counters_.scans_without_accelerometer,
            counters_.accelerometer_by_reason);
}

void DaemonStats::WheelSamples(std::uint64_t taken) {
  std::lock_guard lock(mutex_);
  counters_.wheel_samples += taken;
}

void DaemonStats::WheelSampleFault(const std::string& reason, bool dropped) {
  std::lock_guard lock(mutex_);
  counters_.wheel_samples_dropped += dropped;
  ++counters_.wheel_by_reason["sample:" + reason];
}

void DaemonStats::WheelScan(std::string_view why) {
  std::lock_guard lock(mutex_);
  CountScan(why, counters_.scans_with_wheel, counters_.scans_without_wheel, counters_.wheel_by_reason);
}

void DaemonStats::LabelledCloud(bool published) {
  std::lock_guard lock(mutex_);
  ++(published ? counters_.labelled_clouds_published : counters_.labelled_clouds_skipped);
}

void DaemonStats::Dropped(const std::string& where) {
  std::lock_guard lock(mutex_);
  ++counters_.dropped;
  ++counters_.by_reason["dropped:" + where];
}

void DaemonStats::Rejected(const std::string& code, const std::string& message) {
  std::lock_guard lock(mutex_);
  ++counters_.rejected;
  ++counters_.by_reason["rejected:" + code];
  NoteError(message);
}

void DaemonStats::Error(const std::string& message) {
  std::lock_guard lock(mutex_);
  NoteError(message);
}

void DaemonStats::CommandRefused(const std::string& reason, const std::string& message) {
  std::lock_guard lock(mutex_);
  ++counters_.commands_refused;
  ++counters_.refused_by_reason[reason];
  NoteError(message);
}

void DaemonStats::StageFailed(Stage stage, const std::string& message) {
  std::lock_guard lock(mutex_);
  switch (stage) {
    case Stage::kReceive: ++counters_.receive_errors; break;
    case Stage::kPublish: ++counters_.publish_errors; break;
    case Stage::kBackend: ++counters_.backend_errors; break;
  }
  NoteError(message);
}

void DaemonStats::MiddlewareDropped(const dds::MiddlewareEvent& event) {
  std::lock_guard lock(mutex_);
  switch (event.kind) {
    case dds::DropKind::kSampleLost: counters_.samples_lost += event.count; break;
    case dds::DropKind::kSampleRejected: counters_.samples_rejected += event.count; break;
    case dds::DropKind::kUndeserializable:
      counters_.samples_undeserializable += event.count;
      break;
    case dds::DropKind::kRequestedIncompatibleQos:
    case dds::DropKind::kOfferedIncompatibleQos:
      counters_.incompatible_qos += event.count;
      break;
  }
  counters_.middleware_by_reason[event.Reason()] += event.count;
  NoteError(event.Describe());
}

void DaemonStats::NoteError(const std::string& message) {
  ++counters_.errors;
  counters_.last_error = message;
  counters_.last_error_wall_time = WallSeconds();
}

StatusSnapshot DaemonStats::Snapshot() const {
  std::lock_guard lock(mutex_);
  StatusSnapshot s = counters_;
  std::vector<double> sorted(latencies_ms_.begin(), latencies_ms_.end());
  std::sort(sorted.begin(), sorted.end());
  s.latency_median_ms = Percentile(sorted, 0.5);
  s.latency_p95_ms = Percentile(sorted, 0.95);
  s.latency_p99_ms = Percentile(sorted, 0.99);
  s.latency_max_ms = sorted.empty() ? 0.0 : sorted.back();
  return s;
}

}  // namespace dammloam::daemon
