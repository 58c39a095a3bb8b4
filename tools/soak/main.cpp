// dammloam-soak: a long run of dammloamd as a process. Publishes simulated VLP-16 scans at a
// fixed rate from a publisher process that is SIGKILLed and restarted mid-stream, mixes in
// malformed samples, sends save_map every N scans, and checks that the daemon stayed up, rejected
// every malformed sample with its reason, saved loadable maps and kept its memory flat; reports
// drops, latency and RSS over time. Exit 0 pass, 1 fail (or a run-time error), 2 bad usage or no
// CYCLONEDDS_URI. `--publish-only` is the publisher process itself (started by the soak).
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "tools/bench-latency/report.hpp"
#include "tools/common/dds_tool_main.hpp"
#include "tools/soak/publisher.hpp"
#include "tools/soak/soak_report.hpp"
#include "tools/soak/soak_run.hpp"

namespace {

using namespace dammloam;

constexpr int kExitPass = 0;
constexpr int kExitFail = 1;
constexpr int kExitUsage = 2;
constexpr std::size_t kMaxScans = 100'000'000;  // 58 days at 20 Hz

int RunAndReport(const soak::SoakOptions& o) {
  const soak::SoakResult result = soak::RunSoak(o);
  const std::vector<std::string> failures = soak::Failures(result, o);
  soak::PrintReport(result, o, failures);
  if (!o.rss_csv_path.empty()) soak::WriteRssCsv(result.rss, o.rss_csv_path);
  if (!o.json_path.empty()) bench::WriteJson(o.json_path, soak::ToJson(result, o, failures));
  // A passing run leaves nothing behind in a temporary directory; a failing one keeps its logs.
  if (failures.empty() && o.work_dir.empty() && !o.keep_work_dir) {
    std::filesystem::remove_all(result.work_dir);
  } else {
    std::printf("work directory (logs, maps): %s\n", result.work_dir.c_str());
  }
  return failures.empty() ? kExitPass : kExitFail;
}

struct Flags {
  soak::SoakOptions soak;
  bool publish_only = false;
  std::size_t first = 0;
};

void AddSoakOptions(CLI::App& app, Flags& f) {
  soak::SoakOptions& o = f.soak;
  app.add_option("--scans", o.scans, "valid scans to publish")
      ->check(CLI::Range(std::size_t{1}, kMaxScans));
  app.add_option("--rate", o.rate, "scans per second (the simulated VLP-16 spins at 20 Hz: other rates replay it faster or "
                 "slower)")
      ->check(CLI::Range(0.1, 100.0));
  app.add_option("--malformed-rate", o.malformed_rate,
                 "malformed samples per valid scan, evenly spaced, kinds in turn")
      ->check(CLI::Range(0.0, 0.5));
  app.add_option("--save-every", o.save_every, "scans between save_map commands (0: none)")
      ->check(CLI::Range(std::size_t{0}, kMaxScans));
  app.add_option("--kill-at", o.kill_at,
                 "fraction of the scans after which the publisher is SIGKILLed and restarted "
                 "(0: never)")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--seed", o.seed, "simulator seed (range noise)");
  app.add_option("--domain", o.domain, "DDS domain id (one nobody else uses)")
      ->check(CLI::Range(0u, 232u));
  app.add_option("--max-rss-growth", o.max_rss_growth,
                 "fail when dammloamd's RSS grows more than PCT % over the last half of the run")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--rss-csv", o.rss_csv_path, "write dammloamd's RSS over time (1 Hz) here");
  app.add_option("--json", o.json_path, "also write the report as JSON here");
  app.add_option("--work-dir", o.work_dir,
                 "logs, config and saved maps here (must be empty or new; kept); default: a "
                 "temporary directory, removed when the run passes");
  app.add_flag("--keep-work-dir", o.keep_work_dir, "keep the temporary work directory");
}

// The publisher process's own options, hidden from --help: the soak passes them.
void AddPublisherOptions(CLI::App& app, Flags& f) {
  app.add_flag("--publish-only", f.publish_only, "be the publisher process")->group("");
  app.add_option("--first", f.first, "first scan to publish (--publish-only)")->group("");
}

int RunPublisher(const Flags& f) {
  // stdout carries the reports the soak parses: log lines go to stderr (the publisher's log).
  spdlog::set_default_logger(spdlog::stderr_color_mt("publisher"));
  const soak::SoakOptions& o = f.soak;
  if (f.first >= o.scans) {
    spdlog::error("--first {} is not below --scans {}", f.first, o.scans);
    return kExitUsage;
  }
  return soak::RunPublisher({o.domain, f.first, o.scans, o.rate, o.malformed_rate, o.seed});
}

}  // namespace

int main(int argc, char** argv) {
  Flags f;
  CLI::App app{"dammloam-soak: a long run of dammloamd as a process, with a publisher killed and "
               "restarted, malformed samples and map saves; checks it stays up, rejects every "
               "malformed sample with its reason, saves loadable maps and keeps its memory flat"};
  app.footer("exit codes: 0 pass, 1 fail (the FAIL lines say why), 2 bad usage or no "
             "CYCLONEDDS_URI\nExample (CYCLONEDDS_URI=file://$PWD/deploy/cyclonedds-loopback.xml):"
             "\n  dammloam-soak --scans 10000 --rss-csv rss.csv --json soak.json "
             "--max-rss-growth 5");
  AddSoakOptions(app, f);
  AddPublisherOptions(app, f);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 would exit with its own codes (105, 106, ...): scripts get the documented 2.
    return app.exit(e) == 0 ? kExitPass : kExitUsage;
  }
  // Never on the default network: the soak starts four processes that all talk DDS.
  return tools::RunDdsTool(/*allow_default_network=*/false,
                           [&] { return f.publish_only ? RunPublisher(f) : RunAndReport(f.soak); });
}
