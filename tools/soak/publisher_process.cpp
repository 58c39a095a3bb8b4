#include "tools/soak/publisher_process.hpp"

#include <signal.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "tools/bench-latency/latency_run.hpp"

namespace dammloam::soak {

void SendLedger::Record(const SentSample& sample) {
  std::lock_guard lock(mutex_);
  if (sample.kind == kScanKind) {
    scans_[KeyOf(sample.stamp)] = {sample.scan, sample.sent};
    last_scan_ = sample.scan;
  } else {
    ++malformed_[sample.kind];
  }
  const auto lateness = sample.sent - sample.due;
  timing_.max_lateness_ms = std::max(
      timing_.max_lateness_ms, std::chrono::duration<double, std::milli>(lateness).count());
  if (lateness > bench::kLatePublish) ++timing_.late;
}

std::size_t SendLedger::scans_sent() const {
  std::lock_guard lock(mutex_);
  return scans_.size();
}

std::optional<std::size_t> SendLedger::last_scan() const {
  std::lock_guard lock(mutex_);
  return last_scan_;
}

std::map<std::string, std::uint64_t> SendLedger::malformed_by_kind() const {
  std::lock_guard lock(mutex_);
  return malformed_;
}

std::map<StampKey, SentScan> SendLedger::sent_scans() const {
  std::lock_guard lock(mutex_);
  return scans_;
}

PublishTiming SendLedger::timing() const {
  std::lock_guard lock(mutex_);
  return timing_;
}

PublisherProcess::PublisherProcess(const PublisherOptions& options, SendLedger& ledger,
                                   std::optional<std::size_t> kill_after,
                                   const std::filesystem::path& log)
    : process_(tools::SelfExecutable(), PublisherArgs(options), {log, true}),
      ledger_(ledger),
      kill_after_(kill_after),
      reader_([this] { ReadReports(); }) {}

PublisherProcess::~PublisherProcess() {
  if (!reports_done_) process_.Signal(SIGKILL);  // its pipe closes: the reader sees the end
  reader_.join();
}

std::optional<int> PublisherProcess::Finished() {
  if (!reports_done_) return std::nullopt;
  return process_.Wait(std::chrono::seconds(5));  // the pipe closed: it is exiting
}

void PublisherProcess::ReadReports() {
  // A FILE of its own (dup) so that closing it leaves the ChildProcess's descriptor alone.
  FILE* in = fdopen(dup(process_.stdout_fd()), "r");
  char* line = nullptr;
  std::size_t capacity = 0;
  while (in != nullptr && getline(&line, &capacity, in) >= 0) Handle(line);
  std::free(line);
  if (in != nullptr) std::fclose(in);
  reports_done_ = true;
}

void PublisherProcess::Handle(const std::string& line) {
  const std::optional<SentSample> sample = ParseSent(line);
  if (!sample) {
    spdlog::warn("publisher: unexpected output line '{}'", line.substr(0, line.find('\n')));
    return;
  }
  ledger_.Record(*sample);
  if (kill_after_ && sample->kind == kScanKind && sample->scan == *kill_after_) {
    // Half way to the next sample, so that the scan's fragments are out on loopback.
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    process_.Signal(SIGKILL);
    killed_ = true;
  }
}

}  // namespace dammloam::soak
