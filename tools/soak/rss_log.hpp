#pragma once
// The daemon's resident set over the run, sampled by the soak's parent.
#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

namespace dammloam::soak {

struct RssSample {
  double elapsed_s = 0.0;     // since the log started
  std::size_t scans_sent = 0;  // valid scans published by then
  double rss_mib = 0.0;
};

class RssLog {
 public:
  explicit RssLog(pid_t pid);

  void Sample(std::size_t scans_sent);
  // The first sample taken with at least `scans` scans sent.
  std::optional<RssSample> At(std::size_t scans) const;
  std::optional<RssSample> Last() const;
  double PeakMiB() const;

  const std::vector<RssSample>& samples() const { return samples_; }

 private:
  pid_t pid_;
  std::chrono::steady_clock::time_point start_;
  std::vector<RssSample> samples_;
};

// "elapsed_s,scans_sent,rss_mib" and one row per sample; throws naming the file.
void WriteRssCsv(const std::vector<RssSample>& samples, const std::filesystem::path& file);

// (to - from) / from in %, 0 when `from` is 0.
double GrowthPercent(double from, double to);

}  // namespace dammloam::soak
