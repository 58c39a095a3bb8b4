#pragma once
// One benchmark run: publish scans to dammloamd over DDS at scheduled instants and time the
// Odometry that comes back for each (publish -> receipt of the pose).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "services/dds/point_cloud.hpp"

namespace dammloam::bench {

using Clock = std::chrono::steady_clock;

// The scans of one run in publish order, each with the instant it is due after the start.
class ScanSource {
 public:
  virtual ~ScanSource() = default;
  virtual std::size_t size() const = 0;
  virtual Clock::duration DueAfterStart(std::size_t index) const = 0;
  // Scan `index`, stamped and ready to write, or nullopt while it is not ready yet. Called for
  // 0, 1, 2, ... in order and never blocks: the publisher keeps collecting poses meanwhile.
  virtual std::optional<dds::CloudMessage> TryTake(std::size_t index) = 0;
};

// The daemon's own counters from its Status topic after the run.
struct DaemonCounters {
  std::uint64_t received = 0, processed = 0, dropped = 0, rejected = 0;
  std::map<std::string, std::uint64_t> by_reason;  // "dropped:<where>", "rejected:<code>"
};

struct RunResult {
  double rate = 0;  // Hz (a sequence's recorded rate times the speed factor)
  std::size_t sent = 0, received = 0;
  double median_ms = 0, p99_ms = 0, max_ms = 0;
  double core_median_ms = 0;  // Odometry.processing_ms: features + registration + map
  // Odometry.latency_ms: from the daemon's acceptance of the converted scan to the pose's
  // publication (queues and stages); the rest of the latency is DDS and the conversion.
  double daemon_median_ms = 0, daemon_p99_ms = 0;
  // Publishes later than kLatePublish after their instant, the worst lateness, and how many of
  // the late ones waited for their scan to be read (the read-ahead ran empty).
  std::size_t late_publishes = 0, late_waiting_for_scan = 0;
  double max_lateness_ms = 0;
  std::optional<DaemonCounters> daemon;  // when asked for and a Status arrived after the run
  bool sustained() const { return received == sent; }
  std::size_t drops() const { return sent - received; }
};

// Scheduling jitter of a loaded 2-core machine stays below this; beyond it a publish is "late".
inline constexpr std::chrono::milliseconds kLatePublish{2};

struct RunOptions {
  std::uint32_t domain = 90;
  bool read_daemon_status = false;  // wait for one Status after the run (up to ~3 s)
  std::string no_daemon_hint;       // added to the error when no dammloamd shows up
};

// Waits for dammloamd on the domain, publishes every scan of `source` at its instant, then
// collects the remaining poses for 3 s.
RunResult RunScans(const RunOptions& options, ScanSource& source);

double Percentile(std::vector<double> values, double q);

}  // namespace dammloam::bench
