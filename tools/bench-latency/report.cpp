#include "tools/bench-latency/report.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dammloam::bench {

void PrintRateRow(const RunResult& r) {
  std::printf("rate %5.1f Hz: %zu/%zu poses, latency median %.1f ms, p99 %.1f ms, max %.1f ms, "
              "core median %.1f ms/scan%s\n", r.rate, r.received, r.sent, r.median_ms, r.p99_ms,
              r.max_ms, r.core_median_ms, r.sustained() ? "" : "  (DROPS)");
  std::printf("  inside dammloamd (accepted -> pose published): median %.1f ms, p99 %.1f ms; the "
              "rest is DDS and the cloud's conversion\n", r.daemon_median_ms, r.daemon_p99_ms);
  if (r.late_publishes > 0) {
    std::printf("  LATE publishes: %zu more than %lld ms after their instant (worst %.1f ms; %zu "
                "of them waited for the scan to be read)\n", r.late_publishes,
                static_cast<long long>(kLatePublish.count()), r.max_lateness_ms,
                r.late_waiting_for_scan);
  }
  std::fflush(stdout);
}

void PrintDrops(const RunResult& r) {
  std::printf("  drops: %zu (sent %zu - poses received %zu)\n", r.drops(), r.sent, r.received);
  if (!r.daemon) {
    std::printf("  dammloamd Status: none received after the run (drop counter unknown)\n");
  } else {
    const DaemonCounters& d = *r.daemon;
    std::printf("  dammloamd Status: received %llu, processed %llu, dropped %llu, rejected %llu",
                static_cast<unsigned long long>(d.received),
                static_cast<unsigned long long>(d.processed),
                static_cast<unsigned long long>(d.dropped),
                static_cast<unsigned long long>(d.rejected));
    for (const auto& [reason, count] : d.by_reason) {
      std::printf(", %s %llu", reason.c_str(), static_cast<unsigned long long>(count));
    }
    // Scans that never reached the daemon were lost in DDS (keep-last 4 on its reader).
    std::printf("; lost before the daemon: %llu\n",
                static_cast<unsigned long long>(r.sent > d.received ? r.sent - d.received : 0));
  }
  if (r.late_publishes == 0) {  // otherwise PrintRateRow's LATE line said it
    std::printf("  publish schedule: every scan within %lld ms of its recorded instant (worst "
                "%.1f ms)\n", static_cast<long long>(kLatePublish.count()), r.max_lateness_ms);
  }
  std::fflush(stdout);
}

nlohmann::json ToJson(const RunResult& r) {
  nlohmann::json j{{"rate_hz", r.rate},
                   {"sent", r.sent},
                   {"received", r.received},
                   {"drops", r.drops()},
                   {"latency_median_ms", r.median_ms},
                   {"latency_p99_ms", r.p99_ms},
                   {"latency_max_ms", r.max_ms},
                   {"core_median_ms", r.core_median_ms},
                   {"daemon_median_ms", r.daemon_median_ms},
                   {"daemon_p99_ms", r.daemon_p99_ms},
                   {"late_publishes", r.late_publishes},
                   {"late_waiting_for_scan", r.late_waiting_for_scan},
                   {"max_lateness_ms", r.max_lateness_ms}};
  if (r.daemon) {
    j["daemon_status"] = {{"received", r.daemon->received},
                          {"processed", r.daemon->processed},
                          {"dropped", r.daemon->dropped},
                          {"rejected", r.daemon->rejected},
                          {"by_reason", r.daemon->by_reason}};
  }
  return j;
}

void WriteJson(const std::string& path, const nlohmann::json& report) {
  const std::filesystem::path tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << report.dump(2) << "\n";
    if (!out) throw std::runtime_error(path + ": cannot write the JSON report");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(path + ": cannot write the JSON report: " + ec.message());
}

double PeakResidentMiB() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) != 0) continue;
    std::istringstream fields(line.substr(6));
    double kib = 0.0;
    fields >> kib;
    return kib / 1024.0;
  }
  return 0.0;
}

}  // namespace dammloam::bench
