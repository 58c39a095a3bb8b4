#include "tools/soak/publisher.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "services/dds/dds.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "tools/soak/malformed.hpp"
#include "tools/soak/report_line.hpp"
#include "tools/soak/soak_scene.hpp"

namespace dammloam::soak {
namespace {

using Clock = std::chrono::steady_clock;

constexpr auto kDiscoveryWait = std::chrono::seconds(30);
constexpr auto kDiscoverySettle = std::chrono::milliseconds(300);  // the reader matches us too
constexpr auto kStartDelay = std::chrono::milliseconds(20);

class ScheduledWriter {
 public:
  ScheduledWriter(const dds::Participant& participant, const dds::Topic& topic)
      : writer_(participant, topic, dds::PointsQos()) {}

  bool WaitForDaemon() { return writer_.WaitForReaders(1, kDiscoveryWait); }

  // Writes `cloud` at `due` and reports it on stdout. The report follows the write: a sample
  // reported was handed to DDS. Its instant is the start of the write, as in bench-latency.
  void Publish(const dds::CloudMessage& cloud, std::size_t scan, const std::string& kind,
               Clock::time_point due) const {
    const dds::CloudView view(cloud);
    std::this_thread::sleep_until(due);
    const auto writing = Clock::now();
    writer_.Write(view.get());
    const SentSample sent{scan, kind, cloud.stamp, due.time_since_epoch(),
                          writing.time_since_epoch()};
    std::fputs(FormatSent(sent).c_str(), stdout);
    std::fflush(stdout);
  }

  void WaitForAcks() const { dds_wait_for_acks(writer_.handle(), DDS_SECS(10)); }

 private:
  dds::Writer<dammloam_msg_PointCloud> writer_;
};

// Simulating a scan happens between publishes: when it takes longer than a period, publishes go
// late. Logged (stderr: the publisher's log) per 200 scans, so that lateness can be explained.
class SimulationTimes {
 public:
  void Add(std::size_t scan, Clock::duration took) {
    const double ms = std::chrono::duration<double, std::milli>(took).count();
    total_ms_ += ms;
    max_ms_ = std::max(max_ms_, ms);
    if (++count_ < kBlock) return;
    spdlog::info("publisher: scans {}..{} simulated in {:.1f} ms mean, {:.1f} ms max",
                 scan + 1 - count_, scan, total_ms_ / static_cast<double>(count_), max_ms_);
    *this = {};
  }

 private:
  static constexpr std::size_t kBlock = 200;
  std::size_t count_ = 0;
  double total_ms_ = 0.0, max_ms_ = 0.0;
};

}  // namespace

std::vector<std::string> PublisherArgs(const PublisherOptions& o) {
  return {"--publish-only",   "--domain", std::to_string(o.domain),
          "--first",          std::to_string(o.first),
          "--scans",          std::to_string(o.end),
          "--rate",           std::to_string(o.rate),
          "--malformed-rate", std::to_string(o.malformed_rate),
          "--seed",           std::to_string(o.seed)};
}

int RunPublisher(const PublisherOptions& o) {
  const sim::Simulator simulator = MakeSoakSimulator(o.seed, o.end);
  const dds::Participant participant(static_cast<dds_domainid_t>(o.domain));
  const dds::Topic topic(participant, dammloam_msg_PointCloud_desc, dds::TopicNames{}.points,
                         dds::PointsQos());
  ScheduledWriter writer(participant, topic);
  if (!writer.WaitForDaemon()) {
    spdlog::error("publisher: no dammloamd reader on domain {} within 30 s", o.domain);
    return 3;
  }
  std::this_thread::sleep_for(kDiscoverySettle);
  const auto t0 = Clock::now() + kStartDelay;
  const auto due = [&](std::size_t scan, double extra_periods) {
    const double periods = static_cast<double>(scan - o.first) + extra_periods;
    return t0 + std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double>(periods / o.rate));
  };
  SimulationTimes times;
  for (std::size_t k = o.first; k < o.end; ++k) {
    const auto simulating = Clock::now();
    const dds::CloudMessage cloud = dds::ScanToCloud(simulator.SimulateScan(static_cast<int>(k)),
                                                     "lidar", k);
    times.Add(k, Clock::now() - simulating);
    writer.Publish(cloud, k, kScanKind, due(k, 0.0));
    if (const auto kind = MalformedAfter(k, o.malformed_rate)) {
      writer.Publish(MakeMalformed(*kind, cloud), k, MalformedKinds()[*kind].name, due(k, 0.5));
    }
  }
  writer.WaitForAcks();
  return 0;
}

}  // namespace dammloam::soak
