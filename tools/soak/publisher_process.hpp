#pragma once
// The soak's parent side of a publisher process: starts it, reads its reports into a
// SendLedger on a thread of its own, and SIGKILLs it once it reported the scan it is to die
// after (the mid-stream crash).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "tools/common/child_process.hpp"
#include "tools/soak/publisher.hpp"
#include "tools/soak/report_line.hpp"

namespace dammloam::soak {

using StampKey = std::pair<std::int32_t, std::uint32_t>;
inline StampKey KeyOf(const dammloam_msg_Time& t) { return {t.sec, t.nanosec}; }

// A valid scan as published.
struct SentScan {
  std::size_t scan = 0;
  std::chrono::nanoseconds at{0};  // steady clock since its epoch (SentSample::sent)
};

// How well the publishers kept their schedule.
struct PublishTiming {
  std::size_t late = 0;   // written more than bench::kLatePublish after their instant
  double max_lateness_ms = 0.0;
};

// Everything the publisher processes reported sending: the truth the daemon's counters and the
// poses are compared with. Thread-safe.
class SendLedger {
 public:
  void Record(const SentSample& sample);

  std::size_t scans_sent() const;                // valid scans
  std::optional<std::size_t> last_scan() const;  // index of the last valid scan sent
  std::map<std::string, std::uint64_t> malformed_by_kind() const;
  // Valid scans by stamp.
  std::map<StampKey, SentScan> sent_scans() const;
  PublishTiming timing() const;

 private:
  mutable std::mutex mutex_;
  std::map<StampKey, SentScan> scans_;
  std::optional<std::size_t> last_scan_;
  std::map<std::string, std::uint64_t> malformed_;
  PublishTiming timing_;
};

class PublisherProcess {
 public:
  // Starts `dammloam-soak --publish-only` with `options`; with `kill_after`, SIGKILLs it 10 ms
  // after it reported writing that scan (half way to its next sample).
  PublisherProcess(const PublisherOptions& options, SendLedger& ledger,
                   std::optional<std::size_t> kill_after, const std::filesystem::path& log);
  ~PublisherProcess();  // SIGKILL if still running, then joins the reader
  PublisherProcess(const PublisherProcess&) = delete;
  PublisherProcess& operator=(const PublisherProcess&) = delete;

  // The exit status once the process ended and every report was read; nullopt before.
  std::optional<int> Finished();
  bool killed_by_us() const { return killed_; }

 private:
  void ReadReports();
  void Handle(const std::string& line);

  tools::ChildProcess process_;
  SendLedger& ledger_;
  const std::optional<std::size_t> kill_after_;
  std::atomic<bool> killed_{false};
  std::atomic<bool> reports_done_{false};
  std::thread reader_;  // last: starts once the members above exist
};

}  // namespace dammloam::soak
