#include "tools/bench-latency/latency_run.hpp"

#include <algorithm>
#include <stdexcept>
#include <thread>

#include "services/dds/dds.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::bench {
namespace {

// How often the publisher looks for poses while it waits: the resolution of the latencies.
constexpr auto kPoll = std::chrono::microseconds(500);
constexpr auto kStartDelay = std::chrono::milliseconds(20);
constexpr auto kDrain = std::chrono::seconds(3);         // poses still awaited after the last scan
constexpr auto kStatusWait = std::chrono::seconds(3);    // dammloamd publishes Status at 1 Hz
constexpr auto kDiscoveryWait = std::chrono::seconds(30);

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// The benchmark's side of the daemon's topics, with the QoS the daemon uses.
struct Endpoints {
  dds::Participant participant;
  dds::Topic points_topic, odometry_topic, status_topic;
  dds::Writer<dammloam_msg_PointCloud> points;
  dds::Reader<dammloam_msg_Odometry> odometry;
  dds::Reader<dammloam_msg_DaemonStatus> status;

  explicit Endpoints(std::uint32_t domain, const dds::TopicNames& names = {})
      : participant(static_cast<dds_domainid_t>(domain)),
        points_topic(participant, dammloam_msg_PointCloud_desc, names.points, dds::PointsQos()),
        odometry_topic(participant, dammloam_msg_Odometry_desc, names.odometry,
                       dds::OdometryQos()),
        status_topic(participant, dammloam_msg_DaemonStatus_desc, names.status, dds::StatusQos()),
        points(participant, points_topic, dds::PointsQos()),
        // Volatile: a pose latched from an earlier run must not count as this run's.
        odometry(participant, odometry_topic, {true, 1000, false}),
        status(participant, status_topic, dds::StatusQos()) {}
};

void WaitForDaemon(const Endpoints& dds, const RunOptions& o) {
  const std::string missing = "no dammloamd on domain " + std::to_string(o.domain) +
                              (o.no_daemon_hint.empty() ? "" : " (" + o.no_daemon_hint + ")");
  if (!dds.points.WaitForReaders(1, kDiscoveryWait)) throw std::runtime_error(missing);
  const auto deadline = Clock::now() + kDiscoveryWait;
  while (dds.odometry.MatchedWriters() == 0) {
    if (Clock::now() > deadline) throw std::runtime_error(missing + ": no Odometry writer");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // discovery settles
}

// Publish instants by stamp, and the latency and core time of every pose that comes back.
class PoseCollector {
 public:
  void Sent(const dammloam_msg_Time& stamp, Clock::time_point at) {
    sent_at_[{stamp.sec, stamp.nanosec}] = at;
  }
  void Collect(const dds::Reader<dammloam_msg_Odometry>& reader) {
    reader.TakeEach([&](const dammloam_msg_Odometry& m, const dds_sample_info_t&) {
      const auto it = sent_at_.find({m.header.stamp.sec, m.header.stamp.nanosec});
      if (it == sent_at_.end()) return;
      latencies_ms_.push_back(Ms(Clock::now() - it->second));
      processing_ms_.push_back(m.processing_ms);
      in_daemon_ms_.push_back(m.latency_ms);
    }, 64);
  }
  std::size_t received() const { return latencies_ms_.size(); }
  void Summarise(RunResult& r) const {
    r.received = latencies_ms_.size();
    r.median_ms = Percentile(latencies_ms_, 0.5);
    r.p99_ms = Percentile(latencies_ms_, 0.99);
    r.max_ms = Percentile(latencies_ms_, 1.0);
    r.core_median_ms = Percentile(processing_ms_, 0.5);
    r.daemon_median_ms = Percentile(in_daemon_ms_, 0.5);
    r.daemon_p99_ms = Percentile(in_daemon_ms_, 0.99);
  }

 private:
  std::map<std::pair<std::int32_t, std::uint32_t>, Clock::time_point> sent_at_;
  std::vector<double> latencies_ms_, processing_ms_, in_daemon_ms_;
};

// A scan waiting for its instant, and whether the source had not produced it yet at that instant.
struct AwaitedScan {
  dds::CloudMessage cloud;
  bool starved = false;
};

// Gets scan `index` from the source and waits for its instant, collecting poses meanwhile.
AwaitedScan AwaitScan(ScanSource& source, std::size_t index, Clock::time_point due,
                      const Endpoints& dds, PoseCollector& poses) {
  std::optional<dds::CloudMessage> cloud = source.TryTake(index);
  bool starved = false;
  while (!cloud || Clock::now() < due) {
    poses.Collect(dds.odometry);
    if (cloud) {
      std::this_thread::sleep_until(std::min(due, Clock::now() + kPoll));
    } else {
      starved = starved || Clock::now() >= due;
      std::this_thread::sleep_for(kPoll);
      cloud = source.TryTake(index);
    }
  }
  return {std::move(*cloud), starved};
}

void NoteLateness(Clock::time_point due, Clock::time_point published, bool starved,
                  RunResult& r) {
  r.max_lateness_ms = std::max(r.max_lateness_ms, Ms(published - due));
  if (published - due <= kLatePublish) return;
  ++r.late_publishes;
  if (starved) ++r.late_waiting_for_scan;
}

void PublishAll(ScanSource& source, const Endpoints& dds, PoseCollector& poses, RunResult& r) {
  // Scan 0 is due a little after now, so that getting it ready does not make it late.
  const auto t0 = Clock::now() + kStartDelay;
  for (std::size_t k = 0; k < source.size(); ++k) {
    const auto due = t0 + source.DueAfterStart(k);
    const AwaitedScan scan = AwaitScan(source, k, due, dds, poses);
    const auto published = Clock::now();
    NoteLateness(due, published, scan.starved, r);
    poses.Sent(scan.cloud.stamp, published);
    dds.points.Write(dds::CloudView(scan.cloud).get());
    ++r.sent;
  }
}

void CollectRemaining(const Endpoints& dds, PoseCollector& poses, std::size_t sent) {
  const auto deadline = Clock::now() + kDrain;
  while (Clock::now() < deadline && poses.received() < sent) {
    poses.Collect(dds.odometry);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

DaemonCounters CountersOf(const dammloam_msg_DaemonStatus& s) {
  DaemonCounters c{s.scans_received, s.scans_processed, s.scans_dropped, s.scans_rejected, {}};
  for (std::uint32_t i = 0; i < s.rejected_by_reason._length; ++i) {
    const auto& reason = s.rejected_by_reason._buffer[i];
    c.by_reason[reason.reason != nullptr ? reason.reason : ""] = reason.count;
  }
  return c;
}

// The first Status published after the run settled (older ones may predate the last scans).
std::optional<DaemonCounters> FreshDaemonCounters(
    const dds::Reader<dammloam_msg_DaemonStatus>& reader) {
  reader.TakeEach([](const dammloam_msg_DaemonStatus&, const dds_sample_info_t&) {});
  std::optional<DaemonCounters> counters;
  const auto deadline = Clock::now() + kStatusWait;
  while (!counters && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    reader.TakeEach([&](const dammloam_msg_DaemonStatus& s, const dds_sample_info_t&) {
      counters = CountersOf(s);
    });
  }
  return counters;
}

}  // namespace

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1) + 0.5;
  return values[std::min(values.size() - 1, static_cast<std::size_t>(position))];
}

RunResult RunScans(const RunOptions& options, ScanSource& source) {
  const Endpoints dds(options.domain);
  WaitForDaemon(dds, options);
  PoseCollector poses;
  RunResult r;
  PublishAll(source, dds, poses, r);
  CollectRemaining(dds, poses, r.sent);
  poses.Summarise(r);
  if (options.read_daemon_status) r.daemon = FreshDaemonCounters(dds.status);
  return r;
}

}  // namespace dammloam::bench
