#include "tools/soak/soak_run.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <thread>

#include "io/sequence_meta.hpp"
#include "tools/bench-latency/daemon_child.hpp"
#include "tools/soak/malformed.hpp"
#include "tools/soak/scan_outcomes.hpp"
#include "tools/soak/soak_scene.hpp"

namespace dammloam::soak {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr auto kDaemonStartWait = seconds(30);
constexpr auto kPollPeriod = milliseconds(50);
constexpr auto kRssPeriod = seconds(1);
constexpr auto kDrainQuiet = seconds(3);      // no new pose for this long: the rest is lost
constexpr auto kDrainLimit = seconds(15);
constexpr auto kSaveWait = seconds(660);      // dammloam-command's own timeout plus a minute
constexpr auto kStatusWait = seconds(3);      // Status comes at 1 Hz
constexpr auto kDaemonStopGrace = seconds(300);  // the shutdown save of a large map
constexpr const char* kShutdownSave = "shutdown";

std::string LoadAverage() {
  std::ifstream in("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  in >> one >> five >> fifteen;
  char text[64];
  std::snprintf(text, sizeof(text), "%.2f %.2f %.2f", one, five, fifteen);
  return text;
}

fs::path PrepareWorkDir(const SoakOptions& o) {
  fs::path dir = o.work_dir;
  if (dir.empty()) {
    dir = fs::temp_directory_path() / ("dammloam-soak-" + std::to_string(::getpid()));
  }
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
    throw std::runtime_error("--work-dir " + dir.string() + " exists and is not empty");
  }
  fs::create_directories(dir / "maps");
  fs::create_directories(dir / "logs");
  return fs::absolute(dir);
}

// Commands confined to maps/, a shutdown save, and a size limit the oversized samples exceed.
fs::path WriteDaemonConfig(const fs::path& work_dir) {
  const fs::path file = work_dir / "dammloamd.yaml";
  std::ofstream out(file);
  out << "dammloamd:\n"
      << "  save_map_on_shutdown: \"" << (work_dir / "maps" / kShutdownSave).string() << "\"\n"
      << "  input:\n"
      << "    max_cloud_bytes: " << kMaxCloudBytes << "\n"
      << "  commands:\n"
      << "    enabled: true\n"
      << "    map_root: \"" << (work_dir / "maps").string() << "\"\n";
  if (!out) throw std::runtime_error(file.string() + ": cannot write the daemon's config");
  return file;
}

fs::path WriteSensorMeta(const fs::path& work_dir) {
  const fs::path file = work_dir / "meta.json";
  io::WriteMeta(file, {SoakSensor().name, sim::ToSensorModel(SoakSensor()), io::PointLayout::kXYZITR});
  return file;
}

class Soak {
 public:
  explicit Soak(const SoakOptions& options) : o_(options) {}

  SoakResult Run() {
    const auto start = Clock::now();
    r_.work_dir = PrepareWorkDir(o_);
    r_.load_average_start = LoadAverage();
    StartDaemon();
    if (WaitForDaemon()) {
      PublishAll();
      Drain();
      FinishSaves();
      r_.status = observer_->FreshStatus(kStatusWait);
    }
    StopDaemon();
    CheckSaves();
    Summarise();
    r_.load_average_end = LoadAverage();
    r_.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return r_;
  }

 private:
  void StartDaemon() {
    const fs::path config = WriteDaemonConfig(r_.work_dir);
    observer_ = std::make_unique<DaemonObserver>(o_.domain);
    daemon_ = std::make_unique<bench::DaemonChild>(o_.domain, WriteSensorMeta(r_.work_dir),
                                                   "--config " + config.string(),
                                                   r_.work_dir / "logs" / "dammloamd.log",
                                                   bench::LoopClosure::kOn);  // as deployed
    rss_ = std::make_unique<RssLog>(daemon_->pid());
    saves_ = std::make_unique<MapSaves>(o_.domain, r_.work_dir / "maps", r_.work_dir / "logs");
    spdlog::info("dammloamd pid {} on domain {}; work directory {}", daemon_->pid(), o_.domain,
                 r_.work_dir.string());
  }

  bool WaitForDaemon() {
    const auto deadline = Clock::now() + kDaemonStartWait;
    while (!observer_->DaemonFound()) {
      if (DaemonEnded() || Clock::now() > deadline) {
        spdlog::error("dammloamd did not come up on domain {} (log: {})", o_.domain,
                      (r_.work_dir / "logs" / "dammloamd.log").string());
        return false;
      }
      std::this_thread::sleep_for(milliseconds(20));
    }
    r_.daemon_found = true;
    rss_->Sample(0);
    return true;
  }

  bool DaemonEnded() {
    if (const auto status = daemon_->ExitStatus()) {
      r_.daemon_died = true;
      r_.daemon_exit = status;
      return true;
    }
    return false;
  }

  void StartPublisher(std::size_t first, std::optional<std::size_t> kill_after) {
    const PublisherOptions p{o_.domain, first, o_.scans, o_.rate, o_.malformed_rate, o_.seed};
    const fs::path log =
        r_.work_dir / "logs" / ("publisher-" + std::to_string(r_.publisher_restarts) + ".log");
    publisher_ = std::make_unique<PublisherProcess>(p, ledger_, kill_after, log);
    spdlog::info("publisher started for scans {}..{}{}", first, o_.scans - 1,
                 kill_after ? " (to be killed after scan " + std::to_string(*kill_after) + ")"
                            : std::string());
  }

  std::optional<std::size_t> KillAfter() const {
    if (!(o_.kill_at > 0.0)) return std::nullopt;
    return static_cast<std::size_t>(o_.kill_at * static_cast<double>(o_.scans));
  }

  void PublishAll() {
    StartPublisher(0, KillAfter());
    next_save_ = o_.save_every;
    next_rss_ = Clock::now() + kRssPeriod;
    while (publisher_ && !DaemonEnded()) {
      observer_->Poll(kPollPeriod);
      const std::size_t sent = ledger_.scans_sent();
      SampleRss(sent);  // first: the half and end samples are taken before that scan's save
      RequestDueSaves(sent);
      saves_->Reap();
      LogProgress(sent);
      if (const auto status = publisher_->Finished()) HandlePublisherExit(*status);
    }
    publisher_.reset();  // kills a publisher still running when the daemon died
    rss_->Sample(ledger_.scans_sent());
  }

  void RequestDueSaves(std::size_t sent) {
    while (o_.save_every > 0 && next_save_ <= sent) {
      saves_->Request(next_save_);
      next_save_ += o_.save_every;
    }
  }

  // Every second, and once as the half and the last scan are reached: saves are due at the same
  // counts (multiples of --save-every), so both comparison points sit just before a save, at the
  // same point of the save cycle, while the peak shows what the saves cost.
  void SampleRss(std::size_t sent) {
    const bool milestone = (!half_sampled_ && sent >= o_.scans / 2) ||
                           (!end_sampled_ && sent >= o_.scans);
    if (Clock::now() < next_rss_ && !milestone) return;
    rss_->Sample(sent);
    half_sampled_ = half_sampled_ || sent >= o_.scans / 2;
    end_sampled_ = end_sampled_ || sent >= o_.scans;
    if (Clock::now() >= next_rss_) next_rss_ += kRssPeriod;
  }

  // Tenths of the run: progress lines and the report's blocks.
  std::size_t BlockSize() const { return std::max<std::size_t>(o_.scans / 10, 1); }

  void LogProgress(std::size_t sent) {
    const std::size_t step = BlockSize();
    if (sent < next_progress_ + step) return;
    next_progress_ = sent / step * step;
    const auto& s = observer_->latest_status();
    spdlog::info("{}/{} scans sent, {} poses, RSS {:.1f} MiB, daemon dropped {} rejected {}, "
                 "load {}", sent, o_.scans, observer_->poses().size(),
                 rss_->Last() ? rss_->Last()->rss_mib : 0.0, s ? s->dropped : 0,
                 s ? s->rejected : 0, LoadAverage());
  }

  void HandlePublisherExit(int status) {
    const bool planned_kill = publisher_->killed_by_us();
    publisher_.reset();
    const std::optional<std::size_t> last = ledger_.last_scan();
    const std::size_t next = last ? *last + 1 : 0;
    if (planned_kill) {
      r_.killed_after_scan = last;
      spdlog::info("publisher SIGKILLed after scan {} (exit status {}); restarting at scan {}",
                   last ? *last : 0, status, next);
      if (next < o_.scans) {
        ++r_.publisher_restarts;
        StartPublisher(next, std::nullopt);
      }
      return;
    }
    if (status != 0 || next < o_.scans) {
      r_.publisher_failure = "publisher exited with status " + std::to_string(status) +
                             " after scan " + std::to_string(next) + " of " +
                             std::to_string(o_.scans);
      spdlog::error("{}", r_.publisher_failure);
    }
  }

  // The poses of the last scans are still on their way.
  void Drain() {
    const auto limit = Clock::now() + kDrainLimit;
    auto last_progress = Clock::now();
    std::size_t seen = observer_->poses().size();
    while (Clock::now() < limit && Clock::now() - last_progress < kDrainQuiet &&
           MatchedPoses() < ledger_.scans_sent() && !DaemonEnded()) {
      observer_->Poll(kPollPeriod);
      if (observer_->poses().size() != seen) {
        seen = observer_->poses().size();
        last_progress = Clock::now();
      }
    }
  }

  std::size_t MatchedPoses() const {
    const auto sent = ledger_.sent_scans();
    std::size_t matched = 0;
    for (const auto& [stamp, pose] : observer_->poses()) matched += sent.count(stamp);
    return matched;
  }

  void FinishSaves() {
    const auto deadline = Clock::now() + kSaveWait;
    saves_->Reap();
    while (!saves_->AllAnswered() && Clock::now() < deadline && !DaemonEnded()) {
      observer_->Poll(kPollPeriod);
      saves_->Reap();
    }
  }

  void StopDaemon() {
    if (!r_.daemon_died && !DaemonEnded()) {
      r_.daemon_exit = daemon_->Stop(kDaemonStopGrace);
      spdlog::info("dammloamd stopped with exit status {}", *r_.daemon_exit);
      return;
    }
    spdlog::error("dammloamd died during the soak: exit status {}", r_.daemon_exit.value_or(-1));
  }

  void CheckSaves() {
    if (r_.daemon_found) saves_->AddShutdownSave(kShutdownSave);
    saves_->LoadAll();
    r_.saves = saves_->records();
  }

  void Summarise() {
    r_.scans_sent = ledger_.scans_sent();
    r_.malformed_by_kind = ledger_.malformed_by_kind();
    r_.timing = ledger_.timing();
    r_.duplicate_poses = observer_->duplicate_poses();
    const auto sent = ledger_.sent_scans();
    for (const auto& [stamp, pose] : observer_->poses()) {
      if (sent.count(stamp) == 0) {
        ++r_.poses_unmatched;
        continue;
      }
      ++r_.poses_matched;
      ++r_.pose_status[pose.status];
    }
    const sim::Simulator truth = MakeSoakSimulator(o_.seed, o_.scans);
    const std::vector<ScanOutcome> outcomes = JoinOutcomes(sent, observer_->poses(), truth);
    for (const ScanOutcome& s : outcomes) {
      if (!s.posed) continue;
      r_.latencies_ms.push_back(s.latency_ms);
      r_.max_error_m = std::max(r_.max_error_m, s.error_m);
    }
    r_.rss = rss_->samples();
    r_.blocks = SummariseBlocks(outcomes, o_.scans, BlockSize(), r_.rss);
    r_.rss_start = rss_->At(0);
    r_.rss_half = rss_->At(o_.scans / 2);
    r_.rss_end = rss_->At(o_.scans) ? rss_->At(o_.scans) : rss_->Last();
    r_.rss_peak_mib = rss_->PeakMiB();
  }

  const SoakOptions& o_;
  SoakResult r_;
  SendLedger ledger_;
  std::unique_ptr<DaemonObserver> observer_;
  std::unique_ptr<bench::DaemonChild> daemon_;
  std::unique_ptr<RssLog> rss_;
  std::unique_ptr<MapSaves> saves_;
  std::unique_ptr<PublisherProcess> publisher_;
  Clock::time_point next_rss_;
  bool half_sampled_ = false, end_sampled_ = false;
  std::size_t next_save_ = 0;
  std::size_t next_progress_ = 0;
};

}  // namespace

std::optional<double> SoakResult::RssGrowthPercent() const {
  if (!rss_half || !rss_end) return std::nullopt;
  return GrowthPercent(rss_half->rss_mib, rss_end->rss_mib);
}

SoakResult RunSoak(const SoakOptions& options) { return Soak(options).Run(); }

}  // namespace dammloam::soak
