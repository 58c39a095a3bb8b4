#include "tools/soak/rss_log.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "io/process_memory.hpp"

namespace dammloam::soak {

RssLog::RssLog(pid_t pid) : pid_(pid), start_(std::chrono::steady_clock::now()) {}

void RssLog::Sample(std::size_t scans_sent) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  samples_.push_back({elapsed, scans_sent, io::ResidentSetMiB(pid_)});
}

std::optional<RssSample> RssLog::At(std::size_t scans) const {
  const auto it = std::find_if(samples_.begin(), samples_.end(),
                               [&](const RssSample& s) { return s.scans_sent >= scans; });
  if (it == samples_.end()) return std::nullopt;
  return *it;
}

std::optional<RssSample> RssLog::Last() const {
  if (samples_.empty()) return std::nullopt;
  return samples_.back();
}

double RssLog::PeakMiB() const {
  double peak = 0.0;
  for (const RssSample& s : samples_) peak = std::max(peak, s.rss_mib);
  return peak;
}

void WriteRssCsv(const std::vector<RssSample>& samples, const std::filesystem::path& file) {
  std::ofstream out(file);
  out << "elapsed_s,scans_sent,rss_mib\n";
  for (const RssSample& s : samples) {
    out << s.elapsed_s << ',' << s.scans_sent << ',' << s.rss_mib << '\n';
  }
  if (!out) throw std::runtime_error(file.string() + ": cannot write the RSS log");
}

double GrowthPercent(double from, double to) {
  return from > 0.0 ? 100.0 * (to - from) / from : 0.0;
}

}  // namespace dammloam::soak
