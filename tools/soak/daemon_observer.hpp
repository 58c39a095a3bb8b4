#pragma once
// The soak's view of dammloamd over DDS: every pose with the instant it arrived, and the
// daemon's Status counters.
#include <Eigen/Core>

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "services/dds/dds.hpp"
#include "tools/soak/publisher_process.hpp"

namespace dammloam::soak {

struct PoseArrival {
  std::chrono::nanoseconds at{0};  // steady clock since its epoch, as SentSample::sent
  bool registered = false;
  std::string status;
  double processing_ms = 0.0;      // Odometry.processing_ms: the core's time for the scan
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // in the daemon's world frame
};

// The DaemonStatus fields the soak reports.
struct StatusCounters {
  std::uint64_t received = 0, processed = 0, dropped = 0, rejected = 0, errors = 0;
  std::map<std::string, std::uint64_t> by_reason;  // "rejected:<code>", "dropped:<where>"
  std::uint64_t receive_errors = 0, publish_errors = 0, backend_errors = 0;
  std::uint64_t commands_refused = 0;
  std::uint64_t samples_lost = 0, samples_rejected = 0, samples_undeserializable = 0,
                incompatible_qos = 0;
  double latency_median_ms = 0, latency_p99_ms = 0, latency_max_ms = 0;  // last 100 scans
  std::string last_error;
};

class DaemonObserver {
 public:
  explicit DaemonObserver(std::uint32_t domain);

  // True once the daemon's Odometry and Status writers are matched.
  bool DaemonFound() const;
  // Waits up to `timeout` for poses, records them, and keeps the newest Status.
  void Poll(std::chrono::milliseconds timeout);
  // The first Status published after this call (the counters then include everything sent
  // before it), or nullopt after `timeout`.
  std::optional<StatusCounters> FreshStatus(std::chrono::milliseconds timeout);

  const std::map<StampKey, PoseArrival>& poses() const { return poses_; }
  std::size_t duplicate_poses() const { return duplicate_poses_; }
  const std::optional<StatusCounters>& latest_status() const { return latest_status_; }

 private:
  void TakeStatus();

  dds::Participant participant_;
  dds::Topic odometry_topic_, status_topic_;
  dds::Reader<dammloam_msg_Odometry> odometry_;
  dds::Reader<dammloam_msg_DaemonStatus> status_;
  dds::WaitSet waitset_;
  std::map<StampKey, PoseArrival> poses_;
  std::size_t duplicate_poses_ = 0;
  std::optional<StatusCounters> latest_status_;
};

}  // namespace dammloam::soak
