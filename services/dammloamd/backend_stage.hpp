#pragma once
// The loop-closure back-end on its own thread: AddScan() is cheap (called by the publish
// stage), Process() (retrieval, verification, Ceres) and map saves run on this thread and never
// block odometry. Only built when the back-end library is (DAMMLOAM_HAVE_BACKEND).
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/backend/loop_closing_backend.hpp"
#include "services/dammloamd/command_stage.hpp"
#include "services/dammloamd/daemon_config.hpp"
#include "services/dds/dds.hpp"

namespace dammloam::daemon {

class LoopClosureStage {
 public:
  // verify_loops = false keeps keyframes for saving but examines no loop candidate (as
  // dammloam-odometry --no-loop-closure --save-map does).
  LoopClosureStage(const dds::Participant& participant, const DaemonConfig& config,
                   bool verify_loops);

  void Start();
  // Joins the thread; save requests already queued are carried out first.
  void Stop();
  void AddScan(const OdometryResult& result);

  // Queues a save for the back-end thread, which first integrates every queued keyframe.
  std::future<CommandOutcome> RequestSave(const std::filesystem::path& dir);
  // The same on the caller's thread, for after Stop() (the shutdown save).
  CommandOutcome SaveNow(const std::filesystem::path& dir);

 private:
  struct SaveRequest {
    std::filesystem::path dir;
    std::promise<CommandOutcome> done;
  };

  void Loop();
  void ProcessQueued();
  void ServeSaves(std::vector<SaveRequest>& saves);
  CommandOutcome Save(const std::filesystem::path& dir) const;
  void Publish(const backend::LoopEvent& e);

  std::string map_frame_;
  dds::Topic topic_;
  dds::Writer<dammloam_msg_LoopClosure> writer_;
  backend::LoopClosingBackend backend_;
  std::uint64_t seq_ = 0;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::vector<SaveRequest> saves_;
  std::thread thread_;
};

}  // namespace dammloam::daemon
