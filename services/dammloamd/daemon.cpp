#include "services/dammloamd/daemon.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

#include "core/odometry/unclassified_scan.hpp"
#include "services/dds/messages.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/ros2_messages.hpp"
#include "services/dds/topics.hpp"

#include "services/dammloamd/backend_stage.hpp"
#include "services/dammloamd/map_localization.hpp"

namespace dammloam::daemon {
namespace {

constexpr auto kWakeUp = std::chrono::milliseconds(100);
constexpr std::size_t kNeverDrop = ~std::size_t{0};

double MillisecondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

std::string StampText(const dammloam_msg_Time& t) {
  char text[32];
  std::snprintf(text, sizeof(text), "%d.%09u", t.sec, t.nanosec);
  return text;
}

bool Later(const dammloam_msg_Time& a, const dammloam_msg_Time& b) {
  return std::tie(a.sec, a.nanosec) > std::tie(b.sec, b.nanosec);
}

dds::CloudLimits InputLimits(const DaemonConfig& config) {
  dds::CloudLimits limits = config.limits;
  limits.max_ring = config.sensor.rings;
  return limits;
}

// The ROS 2 input makes the per-point time choice explicit (ros2.deskew).
dds::CloudLimits Ros2InputLimits(const DaemonConfig& config) {
  dds::CloudLimits limits = InputLimits(config);
  limits.point_times = config.ros2.deskew;
  limits.stamp_may_end_scan = true;  // velodyne_pointcloud
  limits.missing_time_hint =
      "set dammloamd.ros2.deskew: off to register clouds without per-point time (no deskew)";
  return limits;
}

// Points into `counts` (keys included): valid while that map is.
std::vector<dammloam_msg_ReasonCount> ReasonCounts(
    const std::map<std::string, std::uint64_t>& counts) {
  std::vector<dammloam_msg_ReasonCount> out;
  out.reserve(counts.size());
  for (const auto& [reason, count] : counts) out.push_back({const_cast<char*>(reason.c_str()), count});
  return out;
}

// An idlc sequence viewing `items` (no copy): valid while the vector is.
template <typename Sequence, typename Item>
void ViewAsSequence(std::vector<Item>& items, Sequence& sequence) {
  sequence._buffer = items.data();
  sequence._length = sequence._maximum = static_cast<std::uint32_t>(items.size());
}

}  // namespace

struct Daemon::Ros2Endpoints {
  Ros2Endpoints(const dds::Participant& participant, const Ros2Config& config)
      : points_topic(participant, sensor_msgs_msg_dds__PointCloud2__desc,
                     dds::Ros2TopicName(config.points_topic), dds::Ros2SensorDataQos()),
        odometry_topic(participant, nav_msgs_msg_dds__Odometry__desc,
                       dds::Ros2TopicName(config.odometry_topic), dds::Ros2OdometryQos()),
        labelled_topic(participant, sensor_msgs_msg_dds__PointCloud2__desc,
                       dds::Ros2TopicName(config.labelled_cloud_topic),
                       dds::Ros2LabelledCloudQos()),
        points_reader(participant, points_topic, dds::Ros2SensorDataQos()),
        odometry_writer(participant, odometry_topic, dds::Ros2OdometryQos()),
        labelled_writer(participant, labelled_topic, dds::Ros2LabelledCloudQos()) {
    if (config.publish_tf) {
      tf_topic.emplace(participant, tf2_msgs_msg_dds__TFMessage__desc, dds::kRos2TfTopic,
                       dds::Ros2TfQos());
      tf_writer.emplace(participant, *tf_topic, dds::Ros2TfQos());
    }
  }

  dds::Topic points_topic, odometry_topic, labelled_topic;
  std::optional<dds::Topic> tf_topic;
  dds::Reader<sensor_msgs_msg_dds__PointCloud2_> points_reader;
  dds::Writer<nav_msgs_msg_dds__Odometry_> odometry_writer;
  dds::Writer<sensor_msgs_msg_dds__PointCloud2_> labelled_writer;
  std::optional<dds::Writer<tf2_msgs_msg_dds__TFMessage_>> tf_writer;  // publish_tf
  std::uint64_t next_seq = 0;  // receive thread: ROS 2 headers carry no seq, the daemon counts
};

Daemon::Daemon(const DaemonConfig& config, const OdometryConfig& odometry_config,
               FaultInjector fault)
    : Daemon(config, odometry_config, backend::BackendParameters{}, std::move(fault)) {}

Daemon::Daemon(const DaemonConfig& config, const OdometryConfig& odometry_config,
               const backend::BackendParameters& backend_config, FaultInjector fault)
    : config_(config),
      odometry_config_(odometry_config),
      extractor_(odometry_config.preprocess, config.sensor),
      odometry_(odometry_config, config.sensor),
      fault_(std::move(fault)),
      predicted_orientation_(odometry_.PredictedOrientation()),
      received_(config.queue_capacity, config.max_backlog),
      featured_(config.queue_capacity, config.max_backlog),
      registered_(config.queue_capacity, kNeverDrop),  // every registered scan is published
      labelled_(kLabelledQueueCapacity, kLabelledBacklog),
      participant_(static_cast<dds_domainid_t>(config.domain)),
      points_topic_(participant_, dammloam_msg_PointCloud_desc, config.topics.points,
                    dds::PointsQos(config.input_depth)),
      odometry_topic_(participant_, dammloam_msg_Odometry_desc, config.topics.odometry,
                      dds::OdometryQos()),
      labelled_topic_(participant_, dammloam_msg_LabelledCloud_desc, config.topics.labelled_cloud,
                      dds::LabelledCloudQos()),
      status_topic_(participant_, dammloam_msg_DaemonStatus_desc, config.topics.status,
                    dds::StatusQos()),
      points_reader_(participant_, points_topic_,
                     {config.input_reliable, config.input_depth, false}),
      odometry_writer_(participant_, odometry_topic_, dds::OdometryQos()),
      labelled_writer_(participant_, labelled_topic_, dds::LabelledCloudQos()),
      status_writer_(participant_, status_topic_, dds::StatusQos()),
      waitset_(participant_) {
  waitset_.Attach(points_reader_);
  if (config.ros2.enabled) {
    ros2_ = std::make_unique<Ros2Endpoints>(participant_, config.ros2);
    waitset_.Attach(ros2_->points_reader);
  }
  // The shutdown save needs keyframes even when loop closure is off.
  if (config.loop_closure || !config.save_map_on_shutdown.empty()) {
    loop_closure_ = std::make_unique<LoopClosureStage>(
        participant_, config, backend_config.loop_closing, config.loop_closure,
        [this](const std::string& message) { StageFailed(Stage::kBackend, message); }, fault_);
  }
  localization_ = std::make_unique<MapLocalization>(backend_config.localizer);
  if (config.imu.enabled) {
    // Without its IMU the daemon still tracks with the LiDAR: a topic the middleware refuses
    // (DDS Security permissions from before the IMU input, say) is an error in Status, not a
    // daemon that does not start.
    try {
      imu_ = std::make_unique<ImuInput>(participant_, config, stats_);
    } catch (const dds::DdsError& e) {
      const std::string message = std::string("IMU input off (the LiDAR alone): ") + e.what();
      spdlog::error("{}", message);
      stats_.Error(message);
    }
  }
  if (config.wheel.enabled) {
    // As the IMU's: a refused topic costs the wheels, never the daemon.
    try {
      wheel_ = std::make_unique<WheelInput>(participant_, config, stats_);
    } catch (const dds::DdsError& e) {
      const std::string message =
          std::string("wheel odometry input off (the LiDAR alone): ") + e.what();
      spdlog::error("{}", message);
      stats_.Error(message);
    }
  }
  commands_ = std::make_unique<CommandStage>(
      participant_, config,
      std::map<std::string, CommandHandler>{
          {"save_map", [this](const std::string& dir) { return SaveMapCommand(dir); }},
          {"relocalize", [this](const std::string& dir) { return RelocalizeCommand(dir); }}},
      CommandEvents{[this](const std::string& message) { CommandFailed(message); },
                    [this](const std::string& reason, const std::string& message) {
                      CommandRefused(reason, message);
                    }});
  middleware_.Watch(points_reader_);
  middleware_.Watch(odometry_writer_);
  middleware_.Watch(labelled_writer_);
  middleware_.Watch(status_writer_);
  if (ros2_) {
    middleware_.Watch(ros2_->points_reader);
    middleware_.Watch(ros2_->odometry_writer);
    middleware_.Watch(ros2_->labelled_writer);
    if (ros2_->tf_writer) middleware_.Watch(*ros2_->tf_writer);
  }
  if (loop_closure_) loop_closure_->WatchEndpoints(middleware_);
  if (imu_) imu_->Watch(middleware_);
  if (wheel_) wheel_->Watch(middleware_);
  commands_->WatchEndpoints(middleware_);
}

Daemon::~Daemon() { Stop(); }

void Daemon::Start() {
  PublishStatus(false, dammloam_msg_STATE_WAITING);
  if (loop_closure_) loop_closure_->Start();
  commands_->Start();
  threads_.emplace_back([this] { LabelledLoop(); });
  threads_.emplace_back([this] { PublishLoop(); });
  threads_.emplace_back([this] { RegistrationLoop(); });
  threads_.emplace_back([this] { FeatureLoop(); });
  threads_.emplace_back([this] { ReceiveLoop(); });
}

void Daemon::Stop() {
  if (threads_.empty()) return;
  stop_ = true;
  waitset_.Wake();
  for (auto& thread : threads_) thread.join();
  threads_.clear();
  commands_->Stop();  // before the back-end: a save_map in work waits for the back-end thread
  if (loop_closure_) loop_closure_->Stop();
  SaveOnShutdown();
  ReportMiddlewareDrops();
  PublishStatus(false, dammloam_msg_STATE_STOPPING);
}

void Daemon::ReceiveLoop() {
  while (!stop_) {
    try {
      waitset_.Wait(kWakeUp);
      const auto take_native = [this] {
        return points_reader_.TakeEach(
            [this](const dammloam_msg_PointCloud& cloud, const dds_sample_info_t&) {
              ReceiveGuarded([&] { HandleCloud(cloud); });
            },
            4);
      };
      const auto take_ros2 = [this] {
        if (!ros2_) return 0;
        return ros2_->points_reader.TakeEach(
            [this](const sensor_msgs_msg_dds__PointCloud2_& cloud, const dds_sample_info_t&) {
              ReceiveGuarded([&] { HandleRos2Cloud(cloud); });
            },
            4);
      };
      // Both inputs in turn until both are empty: neither can starve the other.
      while (!stop_ && take_native() + take_ros2() > 0) {
      }
    } catch (const std::exception& e) {
      StageFailed(Stage::kReceive, std::string("receive stage: ") + e.what());
    }
  }
}

// A failure while handling one sample costs that sample only, not the others taken with it.
void Daemon::ReceiveGuarded(const std::function<void()>& handle) {
  try {
    handle();
  } catch (const std::exception& e) {
    StageFailed(Stage::kReceive, std::string("receive stage: ") + e.what());
  }
}

void Daemon::HandleCloud(const dammloam_msg_PointCloud& cloud) {
  Accept(dds::ViewOf(cloud), cloud.header.seq, InputLimits(config_),
         "PointCloud seq " + std::to_string(cloud.header.seq));
}

void Daemon::HandleRos2Cloud(const sensor_msgs_msg_dds__PointCloud2_& cloud) {
  const std::uint64_t seq = ros2_->next_seq++;
  Accept(dds::ViewOf(cloud), seq, Ros2InputLimits(config_),
         "ROS 2 PointCloud2 #" + std::to_string(seq) + " on " + ros2_->points_topic.name());
}

void Daemon::Accept(const dds::CloudInput& cloud, std::uint64_t seq,
                    const dds::CloudLimits& limits, const std::string& sample) {
  stats_.Received();
  InjectFault(Stage::kReceive);
  dds::CloudConversion conversion = dds::CloudToScan(cloud, limits);
  const dammloam_msg_Time stamp{cloud.stamp.sec, cloud.stamp.nanosec};
  if (!conversion.scan) return Reject(sample, stamp, conversion.code, conversion.error);
  // One timeline for both inputs: the odometry cannot go back in time.
  if (have_last_stamp_ && !Later(stamp, last_stamp_)) {
    const bool duplicate =
        stamp.sec == last_stamp_.sec && stamp.nanosec == last_stamp_.nanosec;
    return Reject(sample, stamp, duplicate ? "duplicate_stamp" : "out_of_order_stamp",
                  std::string(duplicate ? "duplicate" : "out-of-order") + " stamp: not after " +
                      "the last accepted stamp " + StampText(last_stamp_));
  }
  have_last_stamp_ = true;
  last_stamp_ = stamp;
  // The pose is at the scan's first point: a cloud stamped at the end of its sweep gets the
  // stamp of its start on every output.
  const bool restamped = conversion.start_offset != 0.0;
  ReceivedScan item{{restamped ? dds::ToMsgTime(conversion.scan->t_start) : stamp, seq,
                     std::string(cloud.frame_id), std::chrono::steady_clock::now()},
                    std::move(*conversion.scan)};
  const ScanMeta meta = item.meta;
  if (!received_.TryPush(std::move(item))) Drop(meta, "receive_queue_full");
}

void Daemon::Reject(const std::string& sample, const dammloam_msg_Time& stamp,
                    const std::string& code, const std::string& problem) {
  const std::string message =
      "rejected " + sample + " stamp " + StampText(stamp) + " [" + code + "]: " + problem;
  spdlog::warn("{}", message);
  stats_.Rejected(code, message);
  PublishStatus(true, dammloam_msg_STATE_DEGRADED);
}

void Daemon::Drop(const ScanMeta& meta, const std::string& where) {
  spdlog::warn("dropped scan seq {} stamp {} ({}): odometry is falling behind", meta.seq,
               StampText(meta.stamp), where);
  stats_.Dropped(where);
}

void Daemon::FeatureLoop() {
  const auto drop = [this](ReceivedScan&& old) { Drop(old.meta, "backlog_before_features"); };
  while (!stop_) {
    std::optional<ReceivedScan> item = received_.Pop(kWakeUp, drop);
    if (!item) continue;
    try {
      Eigen::Matrix3d R_world_sensor;
      {
        std::lock_guard lock(prediction_mutex_);
        R_world_sensor = predicted_orientation_;
      }
      // Same branch as OdometryPipeline::Extract: the point-to-point ablation skips features.
      ClassifiedScan classified =
          odometry_config_.registration.mode == RegistrationMode::kPointToPoint
              ? UnclassifiedScan(std::move(item->scan), odometry_config_.preprocess,
                                 config_.sensor)
              : extractor_.Extract(std::move(item->scan), R_world_sensor, features_);
      const ScanMeta meta = item->meta;
      if (!featured_.TryPush({item->meta, std::move(classified)})) {
        Drop(meta, "feature_queue_full");
      }
    } catch (const std::exception& e) {
      spdlog::error("feature stage, scan seq {}: {}", item->meta.seq, e.what());
      stats_.Rejected("internal", std::string("feature stage: ") + e.what());
    }
  }
}

void Daemon::RegistrationLoop() {
  const auto drop = [this](FeatureScan&& old) { Drop(old.meta, "backlog_before_registration"); };
  while (!stop_) {
    std::optional<FeatureScan> item = featured_.Pop(kWakeUp, drop);
    if (!item) continue;
    try {
      FeedImu(item->scan.scan.t_start);
      FeedWheel(item->scan.scan.t_start);
      // The map update waits until the pose is on its way: it is not on the latency path.
      OdometryResult result = odometry_.RegisterDeferringMap(std::move(item->scan));
      if (imu_) imu_->Count(result);
      if (wheel_) wheel_->Count(result);
      {
        // Before the result leaves: in lock-step the next scan is sent only after this pose
        // arrives, so its features see exactly this prediction.
        std::lock_guard lock(prediction_mutex_);
        predicted_orientation_ = odometry_.PredictedOrientation();
      }
      const ScanMeta meta = item->meta;
      if (!registered_.TryPush({item->meta, std::move(result)})) Drop(meta, "publish_queue_full");
      odometry_.CommitMap();
    } catch (const std::exception& e) {
      spdlog::error("registration stage, scan seq {}: {}", item->meta.seq, e.what());
      stats_.Rejected("internal", std::string("registration stage: ") + e.what());
    }
  }
}

// The IMU samples that cover the scan, before it is registered (issue 55). A failure here costs
// the scan its gyro, never the scan.
void Daemon::FeedImu(double t_start) {
  if (!imu_) return;
  try {
    imu_->FeedThrough(t_start, odometry_, stop_);
  } catch (const std::exception& e) {
    StageFailed(Stage::kReceive, std::string("IMU input: ") + e.what());
  }
}

// The wheel samples that cover the scan's interval, as FeedImu: a failure costs the scan its
// wheels, never the scan.
void Daemon::FeedWheel(double t_start) {
  if (!wheel_) return;
  try {
    wheel_->FeedThrough(t_start, odometry_, stop_);
  } catch (const std::exception& e) {
    StageFailed(Stage::kReceive, std::string("wheel odometry input: ") + e.what());
  }
}

void Daemon::PublishLoop() {
  auto next_status = std::chrono::steady_clock::now();
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(config_.status_period));
  while (!stop_) {
    std::optional<RegisteredScan> item =
        registered_.Pop(std::chrono::milliseconds(50), [](RegisteredScan&&) {});
    try {
      if (item) Publish(std::move(*item));
      ReportMiddlewareDrops();
      if (std::chrono::steady_clock::now() >= next_status) {
        PublishStatus(false, RunningState());
        next_status += period;
        if (next_status < std::chrono::steady_clock::now()) {
          next_status = std::chrono::steady_clock::now() + period;
        }
      }
    } catch (const std::exception& e) {
      StageFailed(Stage::kPublish, std::string("publish stage: ") + e.what());
    }
  }
}

void Daemon::Publish(RegisteredScan&& item) {
  InjectFault(Stage::kPublish);
  const OdometryResult& r = item.result;
  // In localization mode the pose and status say where the scan is in the loaded map.
  const std::optional<MapPose> located = Locate(r);
  const Eigen::Isometry3d T = located ? located->T_map_sensor : r.T_world_sensor;
  const std::string status_name = !located           ? std::string(Name(r.status))
                                  : located->localized ? "localized"
                                                       : "relocalizing";
  dammloam_msg_Odometry odom = dds::ToMsgOdometry(r, config_.map_frame, item.meta.frame_id,
                                                  status_name);
  odom.pose = dds::ToMsgPose(T);
  odom.header.stamp = item.meta.stamp;
  odom.header.seq = published_;
  odom.input_seq = item.meta.seq;
  odom.latency_ms = MillisecondsSince(item.meta.received);
  odometry_writer_.Write(odom);
  stats_.Processed(odom.latency_ms, Name(r.tracking), Name(r.point_times));

  if (ros2_) {
    // REP 105: the odometry stays continuous in odom; what localization or loop closure adds is
    // map -> odom.
    PublishRos2(item, located ? located->T_map_sensor * r.T_world_sensor.inverse()
                      : loop_closure_ && config_.loop_closure ? loop_closure_->MapFromOdom()
                                                              : Eigen::Isometry3d::Identity());
  }
  // A loaded map is never grown, and the back-end's own map stays as it was for save_map.
  if (loop_closure_ && Registered(r.status) && !located) loop_closure_->AddScan(r);

  const int every = config_.labelled_cloud_every;
  if (every > 0 && published_ % static_cast<std::uint64_t>(every) == 0) {
    QueueLabelled(std::move(item), T);
  }
  ++published_;
}

// The cloud leaves with the scan's points (moved, not copied) for the labelled-cloud thread;
// built only for topics someone reads.
void Daemon::QueueLabelled(RegisteredScan&& item, const Eigen::Isometry3d& T_map_sensor) {
  OdometryResult& r = item.result;
  if (r.deskewed_points.empty() || r.labels.size() != r.deskewed_points.size()) return;
  const bool native = labelled_writer_.MatchedReaders() > 0;
  const bool ros2 = ros2_ && ros2_->labelled_writer.MatchedReaders() > 0;
  if (!native && !ros2) return;
  LabelledJob job{item.meta, T_map_sensor, published_, r.scan_index, native, ros2, {}};
  job.points.points_sensor = std::move(r.deskewed_points);
  job.points.normals = std::move(r.normals);
  job.points.labels = std::move(r.labels);
  if (!labelled_.TryPush(std::move(job))) stats_.LabelledCloud(false);
}

void Daemon::LabelledLoop() {
  const auto skip = [this](LabelledJob&&) { stats_.LabelledCloud(false); };
  while (!stop_) {
    std::optional<LabelledJob> job = labelled_.Pop(kWakeUp, skip);
    if (!job) continue;
    try {
      PublishLabelled(*job);
      stats_.LabelledCloud(true);
    } catch (const std::exception& e) {
      StageFailed(Stage::kPublish, std::string("labelled cloud: ") + e.what());
    }
  }
}

void Daemon::PublishLabelled(LabelledJob& job) {
  dds::LabelledPoints& points = job.points;
  if (job.native) {
    // Only the native cloud carries the map-frame copy (the ROS 2 cloud is in the sensor frame).
    points.points_map.reserve(points.points_sensor.size());
    for (const auto& p : points.points_sensor) points.points_map.push_back(job.T_map_sensor * p);
    dds::CloudMessage cloud = dds::LabelledToCloud(points, job.meta.frame_id, job.meta.seq);
    cloud.stamp = job.meta.stamp;
    const dds::CloudView view(cloud);
    dammloam_msg_LabelledCloud msg{};
    msg.header.stamp = job.meta.stamp;
    msg.header.frame_id = const_cast<char*>(config_.map_frame.c_str());
    msg.header.seq = job.header_seq;
    msg.child_frame_id = const_cast<char*>(job.meta.frame_id.c_str());
    msg.scan_index = job.scan_index;
    msg.pose = dds::ToMsgPose(job.T_map_sensor);
    msg.cloud = view.get();
    labelled_writer_.Write(msg);
  }
  if (job.ros2) {
    dds::CloudMessage cloud = dds::LabelledToRos2Cloud(points, Ros2SensorFrame(job.meta));
    cloud.stamp = job.meta.stamp;
    ros2_->labelled_writer.Write(dds::Ros2CloudView(cloud).get());
  }
}

const std::string& Daemon::Ros2SensorFrame(const ScanMeta& meta) const {
  static const std::string kUnnamed = "sensor";  // a cloud without frame_id still gets TF
  if (!config_.ros2.sensor_frame.empty()) return config_.ros2.sensor_frame;
  return meta.frame_id.empty() ? kUnnamed : meta.frame_id;
}

void Daemon::PublishRos2(const RegisteredScan& item, const Eigen::Isometry3d& T_map_odom) {
  const Ros2Config& c = config_.ros2;
  const std::string& sensor_frame = Ros2SensorFrame(item.meta);
  ros2_->odometry_writer.Write(dds::ToRos2Odometry(item.result, item.meta.stamp, c.odom_frame,
                                                   sensor_frame, config_.sensor.scan_period));
  if (!ros2_->tf_writer) return;
  geometry_msgs_msg_dds__TransformStamped_ transforms[2] = {
      dds::ToRos2Transform(T_map_odom, item.meta.stamp, c.map_frame, c.odom_frame),
      dds::ToRos2Transform(item.result.T_world_sensor, item.meta.stamp, c.odom_frame,
                           sensor_frame)};
  tf2_msgs_msg_dds__TFMessage_ tf{};
  tf.transforms._buffer = transforms;
  tf.transforms._length = tf.transforms._maximum = 2;
  tf.transforms._release = false;
  ros2_->tf_writer->Write(tf);
}

std::optional<MapPose> Daemon::Locate(const OdometryResult& result) {
  return localization_->Locate(result);
}

std::uint8_t Daemon::RunningState() const {
  if (stats_.Snapshot().processed == 0) return dammloam_msg_STATE_WAITING;
  // Odometry goes on, but the map is no longer being corrected: not a healthy state.
  if (loop_closure_ && loop_closure_->Failed()) return dammloam_msg_STATE_DEGRADED;
  if (localization_->Active()) return dammloam_msg_STATE_LOCALIZING;
  return dammloam_msg_STATE_TRACKING;
}

CommandOutcome Daemon::SaveMapCommand(const std::string& dir) {
  if (!loop_closure_) {
    return {false, "no map to save: the back-end is off (dammloamd.loop_closure is false and "
                   "save_map_on_shutdown is empty)"};
  }
  return loop_closure_->RequestSave(dir).get();  // this thread waits, the back-end saves
}

CommandOutcome Daemon::RelocalizeCommand(const std::string& dir) {
  return localization_->Load(dir);
}

void Daemon::CommandFailed(const std::string& message) {
  stats_.Error(message);
  PublishStatus(true, dammloam_msg_STATE_DEGRADED);
}

void Daemon::CommandRefused(const std::string& reason, const std::string& message) {
  stats_.CommandRefused(reason, message);
  PublishStatus(true, dammloam_msg_STATE_DEGRADED);
}

const char* Daemon::LoopClosureState() const {
  if (loop_closure_ && loop_closure_->Failed()) return "failed";
  return loop_closure_ && config_.loop_closure ? "ok" : "off";
}

void Daemon::InjectFault(Stage stage) const {
  if (fault_) fault_(stage);
}

void Daemon::ReportMiddlewareDrops() {
  const std::vector<dds::MiddlewareEvent> events = middleware_.Poll();
  for (const dds::MiddlewareEvent& event : events) {
    spdlog::error("{}", event.Describe());
    stats_.MiddlewareDropped(event);
  }
  if (!events.empty()) PublishStatus(true, dammloam_msg_STATE_DEGRADED);
}

void Daemon::StageFailed(Stage stage, const std::string& message) {
  spdlog::error("{}", message);
  stats_.StageFailed(stage, message);
  try {
    PublishStatus(true, dammloam_msg_STATE_DEGRADED);
  } catch (const std::exception& e) {  // the Status writer may be what failed: counted above
    spdlog::error("{} stage failure not published as a Status: {}", Name(stage), e.what());
  }
}

// Runs in Stop() after every thread has ended, so the map is complete on disk when the process
// exits (SaveMap renames a finished directory into place).
void Daemon::SaveOnShutdown() {
  if (config_.save_map_on_shutdown.empty() || !loop_closure_) return;
  const CommandOutcome outcome = loop_closure_->SaveNow(config_.save_map_on_shutdown);
  if (outcome.ok) {
    spdlog::info("shutdown: {}", outcome.message);
  } else {
    spdlog::error("shutdown: {}", outcome.message);
    stats_.Error("save_map_on_shutdown: " + outcome.message);
  }
}

void Daemon::PublishStatus(bool error_event, std::uint8_t state) {
  const StatusSnapshot s = stats_.Snapshot();
  std::vector<dammloam_msg_ReasonCount> counts = ReasonCounts(s.by_reason);
  std::vector<dammloam_msg_ReasonCount> refused = ReasonCounts(s.refused_by_reason);
  std::vector<dammloam_msg_ReasonCount> middleware = ReasonCounts(s.middleware_by_reason);
  dammloam_msg_DaemonStatus msg{};
  msg.header.stamp = dds::ToMsgTime(std::chrono::duration<double>(
      std::chrono::system_clock::now().time_since_epoch()).count());
  msg.header.frame_id = const_cast<char*>(config_.map_frame.c_str());
  msg.node = const_cast<char*>(config_.node_name.c_str());
  msg.state = error_event ? dammloam_msg_STATE_DEGRADED : state;
  msg.scans_received = s.received;
  msg.scans_processed = s.processed;
  msg.scans_dropped = s.dropped;
  msg.scans_rejected = s.rejected;
  ViewAsSequence(counts, msg.rejected_by_reason);
  msg.latency_median_ms = s.latency_median_ms;
  msg.latency_p95_ms = s.latency_p95_ms;
  msg.latency_p99_ms = s.latency_p99_ms;
  msg.latency_max_ms = s.latency_max_ms;
  msg.error_count = s.errors;
  msg.last_error = const_cast<char*>(s.last_error.c_str());
  msg.last_error_stamp = dds::ToMsgTime(s.last_error_wall_time);
  msg.is_error_event = error_event;
  msg.commands_refused = s.commands_refused;
  ViewAsSequence(refused, msg.refused_by_reason);
  msg.receive_errors = s.receive_errors;
  msg.publish_errors = s.publish_errors;
  msg.backend_errors = s.backend_errors;
  msg.loop_closure = const_cast<char*>(LoopClosureState());
  msg.samples_lost = s.samples_lost;
  msg.samples_rejected = s.samples_rejected;
  msg.samples_undeserializable = s.samples_undeserializable;
  msg.incompatible_qos = s.incompatible_qos;
  ViewAsSequence(middleware, msg.middleware_by_reason);
  msg.tracking = const_cast<char*>(s.tracking.c_str());
  msg.scans_degraded = s.degraded;
  msg.scans_lost = s.lost;
  msg.scans_without_point_times = s.without_point_times;
  std::vector<dammloam_msg_ReasonCount> imu = ReasonCounts(s.imu_by_reason);
  msg.imu_samples = s.imu_samples;
  msg.imu_samples_dropped = s.imu_samples_dropped;
  msg.scans_with_imu = s.scans_with_imu;
  msg.scans_without_imu = s.scans_without_imu;
  ViewAsSequence(imu, msg.imu_by_reason);
  std::vector<dammloam_msg_ReasonCount> wheel = ReasonCounts(s.wheel_by_reason);
  msg.wheel_samples = s.wheel_samples;
  msg.wheel_samples_dropped = s.wheel_samples_dropped;
  msg.scans_with_wheel = s.scans_with_wheel;
  msg.scans_without_wheel = s.scans_without_wheel;
  ViewAsSequence(wheel, msg.wheel_by_reason);
  std::vector<dammloam_msg_ReasonCount> accel = ReasonCounts(s.accelerometer_by_reason);
  msg.scans_with_accelerometer = s.scans_with_accelerometer;
  msg.scans_without_accelerometer = s.scans_without_accelerometer;
  ViewAsSequence(accel, msg.accelerometer_by_reason);
  msg.labelled_clouds_published = s.labelled_clouds_published;
  msg.labelled_clouds_skipped = s.labelled_clouds_skipped;
  std::lock_guard lock(status_mutex_);
  msg.header.seq = status_seq_++;
  status_writer_.Write(msg);
}

}  // namespace dammloam::daemon
