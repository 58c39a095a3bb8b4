#pragma once
// dammloamd's pipeline: four stages on their own threads joined by bounded SPSC queues
//   receive+validate -q1-> features -q2-> registration + map update -q3-> publish poses
//                                                                          -q4-> labelled clouds
// (a thread of their own: a 128-beam cloud takes longer to write than a scan period, and a pose
// must not wait behind it),
// plus an optional loop-closure back-end thread fed by the publish stage (never on the odometry
// path), and a command thread that answers Command samples (save_map runs on the back-end
// thread, relocalize loads the map there and hands it to the publish stage). The feature stage reads the orientation predicted by the registration stage after the
// previous scan, so in lock-step it makes exactly the calls OdometryPipeline::Process makes.
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/odometry/odometry.hpp"
#include "core/odometry/odometry_config.hpp"
#include "core/preprocess/feature_extractor.hpp"
#include "services/dammloamd/command_stage.hpp"
#include "services/dammloamd/daemon_config.hpp"
#include "services/dammloamd/daemon_stats.hpp"
#include "services/dammloamd/imu_input.hpp"
#include "services/dammloamd/stage_queue.hpp"
#include "services/dammloamd/wheel_input.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/middleware_watch.hpp"
#include "services/dds/point_cloud.hpp"
#include "sensor_msgs.h"

namespace dammloam::daemon {

// What travels with a scan through the stages.
struct ScanMeta {
  dammloam_msg_Time stamp{};
  std::uint64_t seq = 0;
  std::string frame_id;
  std::chrono::steady_clock::time_point received;
};

struct ReceivedScan {
  ScanMeta meta;
  Scan scan;
};
struct FeatureScan {
  ScanMeta meta;
  ClassifiedScan scan;
};
struct RegisteredScan {
  ScanMeta meta;
  OdometryResult result;
};
// A labelled cloud on its way out: the scan's points with the pose they are drawn at.
struct LabelledJob {
  ScanMeta meta;
  Eigen::Isometry3d T_map_sensor = Eigen::Isometry3d::Identity();
  std::uint64_t header_seq = 0;  // the pose's Odometry.header.seq
  std::uint64_t scan_index = 0;
  bool native = false, ros2 = false;  // the topics that have readers
  dds::LabelledPoints points;
};

// Defined in backend_stage.hpp / map_localization.hpp.
class LoopClosureStage;
class MapLocalization;
struct MapPose;

class Daemon {
 public:
  // `fault` is a test seam (daemon_stats.hpp); production passes none.
  Daemon(const DaemonConfig& config, const OdometryConfig& odometry_config,
         const backend::BackendParameters& backend_config, FaultInjector fault = {});
  // With the back-end's default parameters.
  Daemon(const DaemonConfig& config, const OdometryConfig& odometry_config,
         FaultInjector fault = {});
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  void Start();
  // Stops every thread (each waits at most ~100 ms per wake-up, a command in work is finished),
  // saves the map if save_map_on_shutdown is set (complete on return) and publishes a final
  // Status.
  void Stop();

  StatusSnapshot Stats() const { return stats_.Snapshot(); }

 private:
  void ReceiveLoop();
  void FeatureLoop();
  void RegistrationLoop();
  void FeedImu(double t_start);
  void FeedWheel(double t_start);
  void PublishLoop();
  void LabelledLoop();

  void ReceiveGuarded(const std::function<void()>& handle);
  void HandleCloud(const dammloam_msg_PointCloud& cloud);
  void HandleRos2Cloud(const sensor_msgs_msg_dds__PointCloud2_& cloud);
  // Both inputs end here: validates, converts and queues one cloud. `sample` names it in errors.
  void Accept(const dds::CloudInput& cloud, std::uint64_t seq, const dds::CloudLimits& limits,
              const std::string& sample);
  void Reject(const std::string& sample, const dammloam_msg_Time& stamp, const std::string& code,
              const std::string& problem);
  void Drop(const ScanMeta& meta, const std::string& where);
  void Publish(RegisteredScan&& item);
  void QueueLabelled(RegisteredScan&& item, const Eigen::Isometry3d& T_map_sensor);
  void PublishLabelled(LabelledJob& job);
  void PublishRos2(const RegisteredScan& item, const Eigen::Isometry3d& T_map_odom);
  const std::string& Ros2SensorFrame(const ScanMeta& meta) const;
  std::optional<MapPose> Locate(const OdometryResult& result);
  void PublishStatus(bool error_event, std::uint8_t state);
  // Counts what DDS dropped since the last call (publish thread, and Stop() after it ended);
  // one Status error event if anything was.
  void ReportMiddlewareDrops();
  std::uint8_t RunningState() const;
  const char* LoopClosureState() const;
  void InjectFault(Stage stage) const;
  // Counts an exception caught in a stage and publishes it as a Status error event.
  void StageFailed(Stage stage, const std::string& message);

  // Command handlers (command thread).
  CommandOutcome SaveMapCommand(const std::string& dir);
  CommandOutcome RelocalizeCommand(const std::string& dir);
  void CommandFailed(const std::string& message);
  void CommandRefused(const std::string& reason, const std::string& message);
  void SaveOnShutdown();

  DaemonConfig config_;
  OdometryConfig odometry_config_;
  FeatureExtractor extractor_;
  FeatureWorkspace features_;  // the feature thread's
  Odometry odometry_;
  DaemonStats stats_;
  FaultInjector fault_;

  // Orientation predicted by the registration stage for the next scan.
  mutable std::mutex prediction_mutex_;
  Eigen::Matrix3d predicted_orientation_;

  // Owned by the receive thread.
  bool have_last_stamp_ = false;
  dammloam_msg_Time last_stamp_{};

  StageQueue<ReceivedScan> received_;
  StageQueue<FeatureScan> featured_;
  StageQueue<RegisteredScan> registered_;
  // Four 262,144-point clouds (OS1-128 x 2048) hold ~40 MiB; two may wait behind the one being
  // written before the oldest is skipped.
  static constexpr std::size_t kLabelledQueueCapacity = 4, kLabelledBacklog = 2;
  StageQueue<LabelledJob> labelled_;

  dds::Participant participant_;
  dds::Topic points_topic_, odometry_topic_, labelled_topic_, status_topic_;
  dds::Reader<dammloam_msg_PointCloud> points_reader_;
  dds::Writer<dammloam_msg_Odometry> odometry_writer_;
  dds::Writer<dammloam_msg_LabelledCloud> labelled_writer_;
  dds::Writer<dammloam_msg_DaemonStatus> status_writer_;
  dds::WaitSet waitset_;
  std::mutex status_mutex_;
  std::uint64_t status_seq_ = 0;
  std::uint64_t published_ = 0;

  // ROS 2 topics (config.ros2.enabled), defined in daemon.cpp; null when off.
  struct Ros2Endpoints;
  std::unique_ptr<Ros2Endpoints> ros2_;

  std::unique_ptr<LoopClosureStage> loop_closure_;   // null: no back-end, no map to save
  std::unique_ptr<MapLocalization> localization_;    // never null
  std::unique_ptr<CommandStage> commands_;
  std::unique_ptr<ImuInput> imu_;                    // null: dammloamd.imu.enabled is false
  std::unique_ptr<WheelInput> wheel_;                // null: dammloamd.wheel.enabled is false
  // Every reader and writer above; polled by the publish thread (ReportMiddlewareDrops).
  dds::MiddlewareWatch middleware_;
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

}  // namespace dammloam::daemon
