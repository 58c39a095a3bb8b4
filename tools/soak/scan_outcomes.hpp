#pragma once
// Every valid scan the soak sent, joined with the pose the daemon published for it (if any) and
// its true pose from the simulator; and the run cut into blocks of scans, so that a trend (the
// daemon slowing down, the odometry drifting, memory growing) shows where it starts.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "tools/simulate/simulator.hpp"
#include "tools/soak/daemon_observer.hpp"
#include "tools/soak/publisher_process.hpp"
#include "tools/soak/rss_log.hpp"

namespace dammloam::soak {

struct ScanOutcome {
  std::size_t scan = 0;
  bool posed = false;
  double latency_ms = 0.0;  // publish -> pose
  double core_ms = 0.0;     // Odometry.processing_ms
  // Distance between the estimated and the true position, both relative to the daemon's first
  // scan (its world frame): the odometry's drift, or its loss of track.
  double error_m = 0.0;
};

// In scan order.
std::vector<ScanOutcome> JoinOutcomes(const std::map<StampKey, SentScan>& sent,
                                      const std::map<StampKey, PoseArrival>& poses,
                                      const sim::Simulator& truth);

struct BlockSummary {
  std::size_t first_scan = 0, end_scan = 0;  // [first, end)
  std::size_t sent = 0, posed = 0;
  double latency_median_ms = 0.0, core_median_ms = 0.0, max_error_m = 0.0;
  double rss_mib = 0.0;  // the last sample before the block's last scan was sent (pre-save)
};

// Blocks of `block_size` scans over [0, total).
std::vector<BlockSummary> SummariseBlocks(const std::vector<ScanOutcome>& outcomes,
                                          std::size_t total, std::size_t block_size,
                                          const std::vector<RssSample>& rss);

}  // namespace dammloam::soak
