#include "services/dammloamd/backend_stage.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <future>
#include <system_error>

#include "services/dds/messages.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "io/mapstore/map_store.hpp"
#include "io/process_memory.hpp"

namespace dammloam::daemon {
namespace {

backend::BackendConfig StageBackendConfig(backend::BackendConfig config, bool verify_loops) {
  if (!verify_loops) config.max_verifications_per_keyframe = 0;
  return config;
}

}  // namespace

LoopClosureStage::LoopClosureStage(const dds::Participant& participant,
                                   const DaemonConfig& config,
                                   const backend::BackendConfig& backend_config, bool verify_loops,
                                   std::function<void(const std::string&)> on_failure,
                                   FaultInjector fault)
    : map_frame_(config.map_frame),
      topic_(participant, dammloam_msg_LoopClosure_desc, config.topics.loop_closure,
             dds::LoopClosureQos()),
      writer_(participant, topic_, dds::LoopClosureQos()),
      backend_(StageBackendConfig(backend_config, verify_loops)),
      on_failure_(std::move(on_failure)),
      fault_(std::move(fault)) {
  backend_.SetSensor(config.sensor);
}

void LoopClosureStage::Start() { thread_ = std::thread([this] { Loop(); }); }

void LoopClosureStage::Stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void LoopClosureStage::AddScan(const OdometryResult& result) {
  backend_.AddScan(result);
  wake_.notify_one();
}

std::future<CommandOutcome> LoopClosureStage::RequestSave(const std::filesystem::path& dir) {
  std::future<CommandOutcome> done;
  {
    std::lock_guard lock(mutex_);
    saves_.push_back({dir, {}});
    done = saves_.back().done.get_future();
  }
  wake_.notify_one();
  return done;
}

CommandOutcome LoopClosureStage::SaveNow(const std::filesystem::path& dir) {
  ProcessQueued();
  return SaveOnOwnThread(dir);
}

void LoopClosureStage::Loop() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    // A save queued while this thread was busy has already notified: do not wait for it.
    if (saves_.empty()) wake_.wait_for(lock, std::chrono::milliseconds(200));
    std::vector<SaveRequest> saves = std::move(saves_);
    saves_.clear();
    if (stop_ && saves.empty()) break;
    lock.unlock();
    ProcessQueued();
    ServeSaves(saves);
    lock.lock();
  }
  // A save accepted before Stop() is still carried out: its requester waits for the answer.
  std::vector<SaveRequest> late = std::move(saves_);
  saves_.clear();
  lock.unlock();
  ServeSaves(late);
}

void LoopClosureStage::ProcessQueued() {
  try {
    if (fault_) fault_(Stage::kBackend);
    for (const auto& event : backend_.Process()) Publish(event);
  } catch (const std::exception& e) {
    failed_ = true;
    on_failure_(std::string("loop closure back-end failed: ") + e.what());
  }
}

void LoopClosureStage::ServeSaves(std::vector<SaveRequest>& saves) {
  for (SaveRequest& request : saves) request.done.set_value(SaveOnOwnThread(request.dir));
  // A save copies the whole map once or twice; without this its freed pages stay resident.
  if (!saves.empty()) io::ReturnFreedMemory();
}

// The copy of the map lands in the allocator arena of the thread that makes it. Made on this
// thread, it interleaved with the back-end's long-lived keyframes and left holes that later
// scans touch again: up to 19 MiB stayed resident after one save in a soak. A thread of its own
// frees all of its arena at once. This thread waits, so the back-end stays still meanwhile.
CommandOutcome LoopClosureStage::SaveOnOwnThread(const std::filesystem::path& dir) const {
  try {
    return std::async(std::launch::async, [this, &dir] { return Save(dir); }).get();
  } catch (const std::system_error& e) {  // no thread to be had: save here rather than not at all
    spdlog::warn("save_map: no thread for the save ({}); saving on the back-end thread", e.what());
    return Save(dir);
  }
}

CommandOutcome LoopClosureStage::Save(const std::filesystem::path& dir) const {
  if (dir.empty()) return {false, "no target directory given"};
  const auto start = std::chrono::steady_clock::now();
  try {
    const backend::MapData map = backend_.ExportMap();
    if (map.keyframes.empty()) {
      return {false, "the map is empty (no keyframe yet): nothing saved to " + dir.string()};
    }
    mapstore::SaveMap(dir, map);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::size_t pose_only = backend_.NumKeyframes() - map.keyframes.size();
    return {true, "saved " + std::to_string(map.keyframes.size()) + " keyframes (" +
                      std::to_string(pose_only) + " revisits kept as poses only), " +
                      std::to_string(map.loops.size()) + " loops, " +
                      std::to_string(map.global_points.size()) + " map points (" +
                      std::to_string(map.vacated_points) + " left out as vacated) to " +
                      dir.string() + " in " + std::to_string(seconds) + " s"};
  } catch (const std::exception& e) {  // io::IoError names the path and the problem
    return {false, std::string("saving the map failed: ") + e.what()};
  }
}

void LoopClosureStage::Publish(const backend::LoopEvent& e) {
  dammloam_msg_LoopClosure msg{};
  msg.header.stamp = dds::ToMsgTime(e.query_stamp);
  msg.header.frame_id = const_cast<char*>(map_frame_.c_str());
  msg.header.seq = seq_++;
  msg.query_keyframe = e.query_keyframe;
  msg.match_keyframe = e.candidate_keyframe;
  msg.query_stamp = dds::ToMsgTime(e.query_stamp);
  msg.match_stamp = dds::ToMsgTime(e.candidate_stamp);
  msg.relative_pose = dds::ToMsgPose(e.T_candidate_query);
  msg.score = e.scan_context_distance;
  msg.accepted = e.accepted;
  msg.reason = const_cast<char*>(e.reason.c_str());
  writer_.Write(msg);
  spdlog::info("loop candidate keyframes {} -> {}: {} ({})", e.query_keyframe,
               e.candidate_keyframe, e.accepted ? "accepted" : "rejected", e.reason);
}

}  // namespace dammloam::daemon
