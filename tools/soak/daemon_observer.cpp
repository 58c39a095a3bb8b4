#include "tools/soak/daemon_observer.hpp"

#include <thread>

#include "services/dds/messages.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::soak {
namespace {

using Clock = std::chrono::steady_clock;

std::map<std::string, std::uint64_t> ReasonMap(const dds_sequence_dammloam_msg_ReasonCount& s) {
  std::map<std::string, std::uint64_t> counts;
  for (std::uint32_t i = 0; i < s._length; ++i) {
    counts[s._buffer[i].reason != nullptr ? s._buffer[i].reason : ""] = s._buffer[i].count;
  }
  return counts;
}

StatusCounters CountersOf(const dammloam_msg_DaemonStatus& s) {
  StatusCounters c;
  c.received = s.scans_received;
  c.processed = s.scans_processed;
  c.dropped = s.scans_dropped;
  c.rejected = s.scans_rejected;
  c.errors = s.error_count;
  c.by_reason = ReasonMap(s.rejected_by_reason);
  c.receive_errors = s.receive_errors;
  c.publish_errors = s.publish_errors;
  c.backend_errors = s.backend_errors;
  c.commands_refused = s.commands_refused;
  c.samples_lost = s.samples_lost;
  c.samples_rejected = s.samples_rejected;
  c.samples_undeserializable = s.samples_undeserializable;
  c.incompatible_qos = s.incompatible_qos;
  c.latency_median_ms = s.latency_median_ms;
  c.latency_p99_ms = s.latency_p99_ms;
  c.latency_max_ms = s.latency_max_ms;
  c.last_error = s.last_error != nullptr ? s.last_error : "";
  return c;
}

}  // namespace

DaemonObserver::DaemonObserver(std::uint32_t domain)
    : participant_(static_cast<dds_domainid_t>(domain)),
      odometry_topic_(participant_, dammloam_msg_Odometry_desc, dds::TopicNames{}.odometry,
                      dds::OdometryQos()),
      status_topic_(participant_, dammloam_msg_DaemonStatus_desc, dds::TopicNames{}.status,
                    dds::StatusQos()),
      // Volatile, deep: every pose of this run, none latched from before it.
      odometry_(participant_, odometry_topic_, {true, 1000, false}),
      status_(participant_, status_topic_, dds::StatusQos()),
      waitset_(participant_) {
  waitset_.Attach(odometry_);
}

bool DaemonObserver::DaemonFound() const {
  return odometry_.MatchedWriters() > 0 && status_.MatchedWriters() > 0;
}

void DaemonObserver::Poll(std::chrono::milliseconds timeout) {
  waitset_.Wait(timeout);
  const auto now = Clock::now().time_since_epoch();
  odometry_.TakeEach([&](const dammloam_msg_Odometry& m, const dds_sample_info_t&) {
    const auto [it, fresh] = poses_.try_emplace(
        KeyOf(m.header.stamp),
        PoseArrival{now, m.registered, m.status != nullptr ? m.status : "", m.processing_ms,
                    dds::FromMsgPose(m.pose).translation()});
    if (!fresh) ++duplicate_poses_;
  }, 256);
  TakeStatus();
}

void DaemonObserver::TakeStatus() {
  status_.TakeEach([this](const dammloam_msg_DaemonStatus& s, const dds_sample_info_t&) {
    latest_status_ = CountersOf(s);
  });
}

std::optional<StatusCounters> DaemonObserver::FreshStatus(std::chrono::milliseconds timeout) {
  TakeStatus();  // what is already here may predate the last samples
  latest_status_.reset();
  const auto deadline = Clock::now() + timeout;
  while (!latest_status_ && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    TakeStatus();
  }
  return latest_status_;
}

}  // namespace dammloam::soak
