#include "tools/soak/soak_report.hpp"

#include <cstdio>
#include <map>

#include "tools/bench-latency/latency_run.hpp"
#include "tools/soak/malformed.hpp"
#include "tools/soak/soak_scene.hpp"

namespace dammloam::soak {
namespace {

constexpr const char* kRejectedPrefix = "rejected:";
constexpr const char* kDroppedPrefix = "dropped:";

// The daemon's counters whose reason starts with `prefix`, keyed by the rest.
std::map<std::string, std::uint64_t> WithPrefix(const SoakResult& r, const std::string& prefix) {
  std::map<std::string, std::uint64_t> out;
  if (!r.status) return out;
  for (const auto& [reason, count] : r.status->by_reason) {
    if (reason.rfind(prefix, 0) == 0) out[reason.substr(prefix.size())] = count;
  }
  return out;
}

std::uint64_t MalformedSent(const SoakResult& r) {
  std::uint64_t total = 0;
  for (const auto& [kind, count] : r.malformed_by_kind) total += count;
  return total;
}

// Samples that never reached the daemon's receive stage (lost in DDS, e.g. at the kill).
std::uint64_t LostBeforeDaemon(const SoakResult& r) {
  if (!r.status) return 0;
  const std::uint64_t sent = r.scans_sent + MalformedSent(r);
  return sent > r.status->received ? sent - r.status->received : 0;
}

void AddSaveFailures(const SoakResult& r, std::vector<std::string>& failures) {
  for (const SaveRecord& s : r.saves) {
    if (s.ok()) continue;
    if (s.after_scans != 0 && s.command_exit != 0) {
      failures.push_back("save_map " + s.name + " failed: " +
                         (s.command_exit ? "dammloam-command exit " +
                                               std::to_string(*s.command_exit) + ": " + s.reply
                                         : std::string("no reply")));
    } else {
      failures.push_back("map " + s.name + " does not load: " + s.load_error);
    }
  }
}

void AddDaemonFailures(const SoakResult& r, std::vector<std::string>& failures) {
  if (!r.daemon_found) failures.push_back("dammloamd never came up");
  if (r.daemon_died) {
    failures.push_back("dammloamd died during the soak (exit status " +
                       std::to_string(r.daemon_exit.value_or(-1)) + ")");
  } else if (r.daemon_exit && *r.daemon_exit != 0) {
    failures.push_back("dammloamd exited with status " + std::to_string(*r.daemon_exit) +
                       " on SIGTERM");
  }
  if (r.daemon_found && !r.status) failures.push_back("no DaemonStatus after the run");
}

void PrintSent(const SoakResult& r, const SoakOptions& o) {
  std::printf("dammloam-soak: %s on the %s scene, %zu scans at %.1f Hz, malformed rate %.3f, "
              "save every %zu scans, %.0f s\n", kSensorName, kSceneName, o.scans, o.rate,
              o.malformed_rate, o.save_every, r.seconds);
  std::printf("  load average (1/5/15 min): start %s, end %s\n", r.load_average_start.c_str(),
              r.load_average_end.c_str());
  std::printf("  sent: %zu scans, %llu malformed; publisher SIGKILLed after scan %s, restarted "
              "%zu time(s)%s\n", r.scans_sent, static_cast<unsigned long long>(MalformedSent(r)),
              r.killed_after_scan ? std::to_string(*r.killed_after_scan).c_str() : "-",
              r.publisher_restarts, r.publisher_failure.empty() ? "" : " (PUBLISHER FAILED)");
  std::printf("  publish schedule: %zu samples more than %lld ms late (worst %.1f ms)\n",
              r.timing.late, static_cast<long long>(bench::kLatePublish.count()),
              r.timing.max_lateness_ms);
}

void PrintReceived(const SoakResult& r) {
  std::printf("  poses: %zu of %zu scans (missing %zu), %zu with an unknown stamp, %zu "
              "duplicates; status:", r.poses_matched, r.scans_sent, r.missing_poses(),
              r.poses_unmatched, r.duplicate_poses);
  for (const auto& [status, count] : r.pose_status) std::printf(" %s %zu", status.c_str(), count);
  std::printf("\n  latency publish -> pose: median %.1f ms, p99 %.1f ms, max %.1f ms; worst "
              "position error against the simulator's truth %.2f m\n",
              bench::Percentile(r.latencies_ms, 0.5), bench::Percentile(r.latencies_ms, 0.99),
              bench::Percentile(r.latencies_ms, 1.0), r.max_error_m);
  if (!r.status) {
    std::printf("  dammloamd Status: none after the run\n");
    return;
  }
  const StatusCounters& s = *r.status;
  std::printf("  dammloamd Status: received %llu, processed %llu, dropped %llu",
              static_cast<unsigned long long>(s.received),
              static_cast<unsigned long long>(s.processed),
              static_cast<unsigned long long>(s.dropped));
  for (const auto& [where, count] : WithPrefix(r, kDroppedPrefix)) {
    std::printf(" (%s %llu)", where.c_str(), static_cast<unsigned long long>(count));
  }
  std::printf(", rejected %llu; lost before the daemon %llu; stage errors receive %llu publish "
              "%llu backend %llu; DDS lost %llu rejected %llu\n",
              static_cast<unsigned long long>(s.rejected),
              static_cast<unsigned long long>(LostBeforeDaemon(r)),
              static_cast<unsigned long long>(s.receive_errors),
              static_cast<unsigned long long>(s.publish_errors),
              static_cast<unsigned long long>(s.backend_errors),
              static_cast<unsigned long long>(s.samples_lost),
              static_cast<unsigned long long>(s.samples_rejected));
}

void PrintRejections(const SoakResult& r) {
  std::printf("  rejections by reason (expected = malformed samples sent):\n");
  for (const RejectionCheck& c : CheckRejections(r)) {
    std::string kinds;
    for (const std::string& k : c.kinds) kinds += (kinds.empty() ? "" : "+") + k;
    std::printf("    %-20s expected %4llu counted %4llu  %s%s\n", c.code.c_str(),
                static_cast<unsigned long long>(c.expected),
                static_cast<unsigned long long>(c.counted), c.ok() ? "ok" : "MISMATCH",
                kinds.empty() ? "" : ("  (" + kinds + ")").c_str());
  }
}

void PrintBlocks(const SoakResult& r) {
  std::printf("  %-13s %6s %6s %9s %9s %9s %9s\n", "scans", "sent", "posed", "latency", "core",
              "max err", "RSS");
  for (const BlockSummary& b : r.blocks) {
    std::printf("  %5zu-%-7zu %6zu %6zu %6.1f ms %6.1f ms %7.2f m %5.0f MiB\n", b.first_scan,
                b.end_scan - 1, b.sent, b.posed, b.latency_median_ms, b.core_median_ms,
                b.max_error_m, b.rss_mib);
  }
}

void PrintMemory(const SoakResult& r) {
  const auto mib = [](const std::optional<RssSample>& s) { return s ? s->rss_mib : 0.0; };
  const auto growth = r.RssGrowthPercent();
  std::printf("  dammloamd RSS (half and end: before the save due there): start %.1f MiB, at half "
              "(scan %zu) %.1f MiB, end (scan %zu) %.1f MiB, peak %.1f MiB; growth over the last "
              "half %s%.2f %%\n", mib(r.rss_start),
              r.rss_half ? r.rss_half->scans_sent : 0, mib(r.rss_half),
              r.rss_end ? r.rss_end->scans_sent : 0, mib(r.rss_end), r.rss_peak_mib,
              growth ? "" : "unknown ", growth.value_or(0.0));
}

void PrintSaves(const SoakResult& r) {
  std::printf("  saves:\n");
  for (const SaveRecord& s : r.saves) {
    std::printf("    %-12s %s", s.name.c_str(), s.ok() ? "ok " : "FAILED ");
    if (s.loaded) {
      std::printf(" loaded: %zu keyframes, %zu map points", s.keyframes, s.map_points);
    } else if (!s.load_error.empty()) {
      std::printf(" load: %s", s.load_error.c_str());
    }
    if (s.after_scans != 0) std::printf("; command %.1f s: %s", s.command_seconds, s.reply.c_str());
    std::printf("\n");
  }
}

nlohmann::json StatusJson(const StatusCounters& s) {
  return {{"received", s.received},
          {"processed", s.processed},
          {"dropped", s.dropped},
          {"rejected", s.rejected},
          {"errors", s.errors},
          {"by_reason", s.by_reason},
          {"receive_errors", s.receive_errors},
          {"publish_errors", s.publish_errors},
          {"backend_errors", s.backend_errors},
          {"commands_refused", s.commands_refused},
          {"samples_lost", s.samples_lost},
          {"samples_rejected", s.samples_rejected},
          {"samples_undeserializable", s.samples_undeserializable},
          {"incompatible_qos", s.incompatible_qos},
          {"latency_median_ms", s.latency_median_ms},
          {"latency_p99_ms", s.latency_p99_ms},
          {"latency_max_ms", s.latency_max_ms},
          {"last_error", s.last_error}};
}

nlohmann::json RssJson(const SoakResult& r) {
  const auto mib = [](const std::optional<RssSample>& s) -> nlohmann::json {
    if (!s) return nullptr;
    return {{"scans_sent", s->scans_sent}, {"rss_mib", s->rss_mib}};
  };
  const auto growth = r.RssGrowthPercent();
  return {{"start", mib(r.rss_start)},
          {"half", mib(r.rss_half)},
          {"end", mib(r.rss_end)},
          {"peak_mib", r.rss_peak_mib},
          {"growth_last_half_pct", growth ? nlohmann::json(*growth) : nlohmann::json(nullptr)},
          {"samples", r.rss.size()}};
}

nlohmann::json SavesJson(const SoakResult& r) {
  nlohmann::json saves = nlohmann::json::array();
  for (const SaveRecord& s : r.saves) {
    saves.push_back({{"name", s.name},
                     {"after_scans", s.after_scans},
                     {"command_exit", s.command_exit ? nlohmann::json(*s.command_exit)
                                                     : nlohmann::json(nullptr)},
                     {"command_seconds", s.command_seconds},
                     {"reply", s.reply},
                     {"loaded", s.loaded},
                     {"load_error", s.load_error},
                     {"keyframes", s.keyframes},
                     {"loops", s.loops},
                     {"map_points", s.map_points},
                     {"ok", s.ok()}});
  }
  return saves;
}

nlohmann::json BlocksJson(const SoakResult& r) {
  nlohmann::json blocks = nlohmann::json::array();
  for (const BlockSummary& b : r.blocks) {
    blocks.push_back({{"first_scan", b.first_scan}, {"end_scan", b.end_scan}, {"sent", b.sent},
                      {"posed", b.posed}, {"latency_median_ms", b.latency_median_ms},
                      {"core_median_ms", b.core_median_ms}, {"max_error_m", b.max_error_m},
                      {"rss_mib", b.rss_mib}});
  }
  return blocks;
}

nlohmann::json RejectionsJson(const SoakResult& r) {
  nlohmann::json checks = nlohmann::json::array();
  for (const RejectionCheck& c : CheckRejections(r)) {
    checks.push_back({{"code", c.code}, {"kinds", c.kinds}, {"expected", c.expected},
                      {"counted", c.counted}, {"ok", c.ok()}});
  }
  return checks;
}

}  // namespace

std::vector<RejectionCheck> CheckRejections(const SoakResult& r) {
  std::map<std::string, RejectionCheck> by_code;
  for (const MalformedKind& kind : MalformedKinds()) {
    RejectionCheck& c = by_code[kind.code];
    c.code = kind.code;
    c.kinds.push_back(kind.name);
    const auto sent = r.malformed_by_kind.find(kind.name);
    if (sent != r.malformed_by_kind.end()) c.expected += sent->second;
  }
  for (const auto& [code, count] : WithPrefix(r, kRejectedPrefix)) {
    by_code[code].code = code;
    by_code[code].counted = count;
  }
  std::vector<RejectionCheck> checks;
  for (auto& [code, check] : by_code) checks.push_back(std::move(check));
  return checks;
}

std::vector<std::string> Failures(const SoakResult& r, const SoakOptions& o) {
  std::vector<std::string> failures;
  AddDaemonFailures(r, failures);
  if (!r.publisher_failure.empty()) failures.push_back(r.publisher_failure);
  for (const RejectionCheck& c : CheckRejections(r)) {
    if (c.ok()) continue;
    failures.push_back("rejections '" + c.code + "': " + std::to_string(c.expected) +
                       " malformed samples sent, " + std::to_string(c.counted) +
                       " rejected with that reason");
  }
  AddSaveFailures(r, failures);
  const auto growth = r.RssGrowthPercent();
  if (o.max_rss_growth && (!growth || *growth > *o.max_rss_growth)) {
    char text[160];
    std::snprintf(text, sizeof(text), "RSS growth over the last half %.2f %% exceeds %.2f %%",
                  growth.value_or(0.0), *o.max_rss_growth);
    failures.push_back(growth ? text : "RSS growth unknown (the run did not reach its half)");
  }
  return failures;
}

void PrintReport(const SoakResult& r, const SoakOptions& o,
                 const std::vector<std::string>& failures) {
  PrintSent(r, o);
  PrintReceived(r);
  PrintRejections(r);
  PrintBlocks(r);
  PrintMemory(r);
  PrintSaves(r);
  std::printf("  dammloamd: %s, exit status %s\n",
              r.daemon_died ? "DIED during the soak" : "alive until stopped",
              r.daemon_exit ? std::to_string(*r.daemon_exit).c_str() : "unknown");
  if (failures.empty()) {
    std::printf("PASS\n");
  } else {
    for (const std::string& f : failures) std::printf("FAIL: %s\n", f.c_str());
  }
  std::fflush(stdout);
}

nlohmann::json ToJson(const SoakResult& r, const SoakOptions& o,
                      const std::vector<std::string>& failures) {
  return {{"sensor", kSensorName},
          {"scene", kSceneName},
          {"scans", o.scans},
          {"rate_hz", o.rate},
          {"malformed_rate", o.malformed_rate},
          {"save_every", o.save_every},
          {"seconds", r.seconds},
          {"load_average_start", r.load_average_start},
          {"load_average_end", r.load_average_end},
          {"sent", {{"scans", r.scans_sent}, {"malformed_by_kind", r.malformed_by_kind}}},
          {"publisher",
           {{"killed_after_scan", r.killed_after_scan ? nlohmann::json(*r.killed_after_scan)
                                                      : nlohmann::json(nullptr)},
            {"restarts", r.publisher_restarts},
            {"failure", r.publisher_failure},
            {"late_publishes", r.timing.late},
            {"max_lateness_ms", r.timing.max_lateness_ms}}},
          {"poses",
           {{"received", r.poses_matched},
            {"missing", r.missing_poses()},
            {"unknown_stamp", r.poses_unmatched},
            {"duplicates", r.duplicate_poses},
            {"by_status", r.pose_status}}},
          {"latency_ms",
           {{"median", bench::Percentile(r.latencies_ms, 0.5)},
            {"p99", bench::Percentile(r.latencies_ms, 0.99)},
            {"max", bench::Percentile(r.latencies_ms, 1.0)}}},
          {"max_position_error_m", r.max_error_m},
          {"blocks", BlocksJson(r)},
          {"daemon_status", r.status ? StatusJson(*r.status) : nlohmann::json(nullptr)},
          {"lost_before_daemon", LostBeforeDaemon(r)},
          {"rejections", RejectionsJson(r)},
          {"rss", RssJson(r)},
          {"saves", SavesJson(r)},
          {"daemon",
           {{"died", r.daemon_died},
            {"exit_status",
             r.daemon_exit ? nlohmann::json(*r.daemon_exit) : nlohmann::json(nullptr)}}},
          {"failures", failures},
          {"passed", failures.empty()}};
}

}  // namespace dammloam::soak
