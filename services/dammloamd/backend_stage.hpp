#pragma once
// The loop-closure back-end on its own thread: AddScan() is cheap (called by the publish
// stage), Process() (retrieval, verification, Ceres) and map saves run on this thread and never
// block odometry.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/backend/loop_closing_backend.hpp"
#include "services/dammloamd/command_stage.hpp"
#include "services/dammloamd/daemon_config.hpp"
#include "services/dammloamd/daemon_stats.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/middleware_watch.hpp"

namespace dammloam::daemon {

class LoopClosureStage {
 public:
  // verify_loops = false keeps keyframes for saving but examines no loop candidate (as
  // dammloam-odometry --no-loop-closure --save-map does). on_failure gets the text of every
  // exception a back-end pass throws (on the back-end thread, or the caller's in SaveNow).
  LoopClosureStage(const dds::Participant& participant, const DaemonConfig& config,
                   const backend::BackendConfig& backend_config, bool verify_loops,
                   std::function<void(const std::string&)> on_failure, FaultInjector fault = {});

  void Start();
  // Lets `watch` report what DDS drops on this stage's LoopClosure writer.
  void WatchEndpoints(dds::MiddlewareWatch& watch) const { watch.Watch(writer_); }
  // Joins the thread; save requests already queued are carried out first.
  void Stop();
  void AddScan(const OdometryResult& result);
  // map -> odom as the latest pose-graph solve left it (identity before any).
  Eigen::Isometry3d MapFromOdom() const { return backend_.MapFromOdom(); }

  // Queues a save for the back-end thread, which first integrates every queued keyframe.
  std::future<CommandOutcome> RequestSave(const std::filesystem::path& dir);
  // The same on the caller's thread, for after Stop() (the shutdown save).
  CommandOutcome SaveNow(const std::filesystem::path& dir);

  // A back-end pass has thrown. Stays set for the rest of the run: after a pass that stopped
  // half-way the pose graph's state is unknown, so loop closure cannot be called healthy again.
  bool Failed() const { return failed_; }

 private:
  struct SaveRequest {
    std::filesystem::path dir;
    std::promise<CommandOutcome> done;
  };

  void Loop();
  void ProcessQueued();
  void ServeSaves(std::vector<SaveRequest>& saves);
  CommandOutcome Save(const std::filesystem::path& dir) const;
  CommandOutcome SaveOnOwnThread(const std::filesystem::path& dir) const;
  void Publish(const backend::LoopEvent& e);

  std::string map_frame_;
  dds::Topic topic_;
  dds::Writer<dammloam_msg_LoopClosure> writer_;
  backend::LoopClosingBackend backend_;
  std::function<void(const std::string&)> on_failure_;
  FaultInjector fault_;
  std::atomic<bool> failed_{false};
  std::uint64_t seq_ = 0;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::vector<SaveRequest> saves_;
  std::thread thread_;
};

}  // namespace dammloam::daemon
