#pragma once
// Counters and latency window behind the Status topic; every daemon thread reports here.
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>

namespace dammloam::daemon {

struct StatusSnapshot {
  std::uint64_t received = 0, processed = 0, dropped = 0, rejected = 0, errors = 0;
  std::map<std::string, std::uint64_t> by_reason;  // "rejected:<code>" and "dropped:<where>"
  double latency_median_ms = 0, latency_p95_ms = 0, latency_p99_ms = 0, latency_max_ms = 0;
  std::string last_error;
  double last_error_wall_time = 0.0;  // seconds since the epoch
};

class DaemonStats {
 public:
  void Received();
  void Processed(double latency_ms);
  void Dropped(const std::string& where);
  void Rejected(const std::string& code, const std::string& message);
  // An error that is not about a scan (a failed command): counted and shown as last_error.
  void Error(const std::string& message);
  StatusSnapshot Snapshot() const;

 private:
  static constexpr std::size_t kLatencyWindow = 100;
  mutable std::mutex mutex_;
  StatusSnapshot counters_;
  std::deque<double> latencies_ms_;
};

}  // namespace dammloam::daemon
