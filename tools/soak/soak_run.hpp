#pragma once
// One soak run: dammloamd as a child process, simulated scans from a publisher process that is
// SIGKILLed and restarted mid-stream, malformed samples mixed in, save_map commands on a
// schedule; what was sent against what the daemon reported, its memory over time and its maps.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tools/soak/daemon_observer.hpp"
#include "tools/soak/map_saves.hpp"
#include "tools/soak/publisher_process.hpp"
#include "tools/soak/rss_log.hpp"
#include "tools/soak/scan_outcomes.hpp"

namespace dammloam::soak {

struct SoakOptions {
  std::uint32_t domain = 197;
  std::size_t scans = 10000;
  double rate = 20.0;             // Hz of wall time
  double malformed_rate = 0.01;   // malformed samples per valid scan
  std::size_t save_every = 1000;  // scans between save_map commands; 0: none
  double kill_at = 0.4;           // fraction of the scans after which the publisher dies; 0: never
  std::uint64_t seed = 1;
  std::optional<double> max_rss_growth;  // % over the last half; checked only when given
  std::string json_path, rss_csv_path;
  std::filesystem::path work_dir;  // empty: a fresh temporary directory
  bool keep_work_dir = false;
};

struct SoakResult {
  std::filesystem::path work_dir;
  double seconds = 0.0;
  std::string load_average_start, load_average_end;  // /proc/loadavg: 1, 5, 15 min

  // Sent (as the publishers reported it).
  std::size_t scans_sent = 0;
  std::map<std::string, std::uint64_t> malformed_by_kind;
  PublishTiming timing;
  std::optional<std::size_t> killed_after_scan;
  std::size_t publisher_restarts = 0;
  std::string publisher_failure;  // empty: every publisher did its part

  // Received.
  std::size_t poses_matched = 0;    // poses of valid scans sent
  std::size_t poses_unmatched = 0;  // poses whose stamp no valid scan had
  std::size_t duplicate_poses = 0;
  std::map<std::string, std::size_t> pose_status;  // Odometry.status of the matched poses
  std::vector<double> latencies_ms;                // publish -> pose, matched poses
  double max_error_m = 0.0;  // worst distance of a pose from the truth (ScanOutcome::error_m)
  std::optional<StatusCounters> status;            // the daemon's, after the run settled

  // The daemon's memory.
  std::vector<RssSample> rss;
  // Half and end: as the scan at half and the last scan are sent, before their saves start.
  std::optional<RssSample> rss_start, rss_half, rss_end;
  double rss_peak_mib = 0.0;

  std::vector<SaveRecord> saves;
  std::vector<BlockSummary> blocks;  // tenths of the run

  // The daemon process.
  bool daemon_found = false;
  bool daemon_died = false;        // ended before the soak stopped it
  std::optional<int> daemon_exit;  // exit status (after SIGTERM, or when it died)

  std::size_t missing_poses() const { return scans_sent - poses_matched; }
  std::optional<double> RssGrowthPercent() const;
};

// Throws std::runtime_error for set-up failures (work directory, config, no daemon binary).
SoakResult RunSoak(const SoakOptions& options);

}  // namespace dammloam::soak
