#include "tools/soak/scan_outcomes.hpp"

#include <algorithm>
#include <chrono>

#include "services/dds/point_cloud.hpp"
#include "tools/bench-latency/latency_run.hpp"

namespace dammloam::soak {
namespace {

double StampSeconds(const StampKey& key) {
  return dds::ToSeconds(dammloam_msg_Time{key.first, key.second});
}

// The true pose of each scan relative to the first one the daemon posed.
class TruePositions {
 public:
  TruePositions(const sim::Simulator& truth, const std::map<StampKey, PoseArrival>& poses,
                const std::map<StampKey, SentScan>& sent)
      : truth_(truth) {
    for (const auto& [stamp, scan] : sent) {
      if (poses.count(stamp) == 0) continue;
      T_start_inverse_ = truth_.PoseAt(StampSeconds(stamp)).inverse();  // the earliest posed
      break;
    }
  }
  Eigen::Vector3d At(const StampKey& stamp) const {
    return (T_start_inverse_ * truth_.PoseAt(StampSeconds(stamp))).translation();
  }

 private:
  const sim::Simulator& truth_;
  Eigen::Isometry3d T_start_inverse_ = Eigen::Isometry3d::Identity();
};

std::vector<double> Column(const std::vector<ScanOutcome>& rows, double ScanOutcome::*field) {
  std::vector<double> values;
  for (const ScanOutcome& r : rows) {
    if (r.posed) values.push_back(r.*field);
  }
  return values;
}

// The last sample taken before scan `scans` was sent: before a save due there started.
double RssBefore(const std::vector<RssSample>& rss, std::size_t scans) {
  double mib = 0.0;
  for (const RssSample& s : rss) {
    if (s.scans_sent >= scans) break;
    mib = s.rss_mib;
  }
  return mib;
}

}  // namespace

std::vector<ScanOutcome> JoinOutcomes(const std::map<StampKey, SentScan>& sent,
                                      const std::map<StampKey, PoseArrival>& poses,
                                      const sim::Simulator& truth) {
  const TruePositions true_positions(truth, poses, sent);
  std::vector<ScanOutcome> rows;
  rows.reserve(sent.size());
  for (const auto& [stamp, scan] : sent) {
    ScanOutcome row;
    row.scan = scan.scan;
    const auto pose = poses.find(stamp);
    if (pose != poses.end()) {
      row.posed = true;
      row.latency_ms = std::chrono::duration<double, std::milli>(pose->second.at - scan.at).count();
      row.core_ms = pose->second.processing_ms;
      row.error_m = (pose->second.position - true_positions.At(stamp)).norm();
    }
    rows.push_back(row);
  }
  std::sort(rows.begin(), rows.end(),
            [](const ScanOutcome& a, const ScanOutcome& b) { return a.scan < b.scan; });
  return rows;
}

std::vector<BlockSummary> SummariseBlocks(const std::vector<ScanOutcome>& outcomes,
                                          std::size_t total, std::size_t block_size,
                                          const std::vector<RssSample>& rss) {
  std::vector<BlockSummary> blocks;
  auto row = outcomes.begin();
  for (std::size_t first = 0; first < total; first += block_size) {
    BlockSummary b;
    b.first_scan = first;
    b.end_scan = std::min(total, first + block_size);
    const auto begin = row;
    while (row != outcomes.end() && row->scan < b.end_scan) ++row;
    const std::vector<ScanOutcome> in_block(begin, row);
    b.sent = in_block.size();
    for (const ScanOutcome& r : in_block) {
      b.posed += r.posed ? 1 : 0;
      if (r.posed) b.max_error_m = std::max(b.max_error_m, r.error_m);
    }
    b.latency_median_ms = bench::Percentile(Column(in_block, &ScanOutcome::latency_ms), 0.5);
    b.core_median_ms = bench::Percentile(Column(in_block, &ScanOutcome::core_ms), 0.5);
    b.rss_mib = RssBefore(rss, b.end_scan);
    blocks.push_back(b);
  }
  return blocks;
}

}  // namespace dammloam::soak
