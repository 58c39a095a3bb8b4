#include "tools/bridge/dds_feed.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <stdexcept>

#include "io/bag/ros2_output.hpp"
#include "services/dds/dds.hpp"

namespace dammloam::bridge {
namespace {

using Clock = std::chrono::steady_clock;

std::shared_ptr<const std::string> SharedBytes(std::string bytes) {
  return std::make_shared<const std::string>(std::move(bytes));
}

CloudStamp ToStamp(const dammloam_msg_Time& t) { return {t.sec, t.nanosec}; }

// The trajectory as a LINE_LIST (io/bag's marker writer draws pairs): one vertex per
// `spacing` metres travelled, bounded by dropping every other vertex when it grows too long.
class Trajectory {
 public:
  explicit Trajectory(double spacing) : spacing_(spacing) {}
  void Add(const Eigen::Vector3d& position) {
    if (!vertices_.empty() && (position - vertices_.back()).norm() < spacing_) return;
    vertices_.push_back(position);
    if (vertices_.size() > kMaxVertices) {
      std::vector<Eigen::Vector3d> thinned;
      for (std::size_t i = 0; i < vertices_.size(); i += 2) thinned.push_back(vertices_[i]);
      vertices_ = std::move(thinned);
      spacing_ *= 2;
    }
  }
  std::string MarkerArrayCdr(const CloudStamp& stamp, const std::string& frame) const {
    io::LineMarker marker;
    marker.ns = "trajectory";
    for (std::size_t i = 1; i < vertices_.size(); ++i) {
      marker.lines.emplace_back(vertices_[i - 1], vertices_[i]);
    }
    marker.rgba[0] = 0.f;  // cyan
    marker.rgba[1] = 1.f;
    marker.rgba[2] = 1.f;
    marker.width = 0.06;
    const std::vector<std::uint8_t> bytes = io::LineMarkerArrayCdr(stamp, frame, marker);
    return {bytes.begin(), bytes.end()};
  }
  bool empty() const { return vertices_.empty(); }

 private:
  static constexpr std::size_t kMaxVertices = 20'000;
  double spacing_;
  std::vector<Eigen::Vector3d> vertices_;
};

}  // namespace

void RunDdsFeed(const FeedConfig& config, WsServer& server, const std::atomic<bool>& stop) {
  const dds::Participant participant(static_cast<dds_domainid_t>(config.domain));
  const dds::Topic odometry_topic(participant, dammloam_msg_Odometry_desc, config.topics.odometry,
                                  dds::OdometryQos());
  const dds::Topic cloud_topic(participant, dammloam_msg_LabelledCloud_desc,
                               config.topics.labelled_cloud, dds::LabelledCloudQos());
  const dds::Topic loop_topic(participant, dammloam_msg_LoopClosure_desc,
                              config.topics.loop_closure, dds::LoopClosureQos());
  const dds::Topic status_topic(participant, dammloam_msg_DaemonStatus_desc, config.topics.status,
                                dds::StatusQos());
  const dds::Reader<dammloam_msg_Odometry> odometry(participant, odometry_topic,
                                                    dds::OdometryQos());
  const dds::Reader<dammloam_msg_LabelledCloud> clouds(participant, cloud_topic,
                                                       dds::LabelledCloudQos());
  const dds::Reader<dammloam_msg_LoopClosure> loops(participant, loop_topic, dds::LoopClosureQos());
  const dds::Reader<dammloam_msg_DaemonStatus> status(participant, status_topic, dds::StatusQos());
  dds::WaitSet waitset(participant);
  for (const dds::ReaderBase* r : {static_cast<const dds::ReaderBase*>(&odometry),
                                   static_cast<const dds::ReaderBase*>(&clouds),
                                   static_cast<const dds::ReaderBase*>(&loops),
                                   static_cast<const dds::ReaderBase*>(&status)}) {
    waitset.Attach(*r);
  }

  VoxelMap map(config.map);
  LoopLines loop_lines;
  Trajectory trajectory(config.trajectory_spacing_m);
  BridgeCounters counters;
  std::string map_frame = "map";
  CloudStamp newest{};
  auto next_map = Clock::now();
  const auto map_period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(config.map_period_s));

  while (!stop) {
    waitset.Wait(std::chrono::milliseconds(100));
    odometry.TakeEach([&](const dammloam_msg_Odometry& o, const dds_sample_info_t&) {
      const std::uint64_t t = StampNanoseconds(o.header.stamp);
      const Eigen::Vector3d position(o.pose.position.x, o.pose.position.y, o.pose.position.z);
      loop_lines.AddPose(t, position);
      trajectory.Add(position);
      if (o.header.frame_id != nullptr && o.header.frame_id[0] != '\0') map_frame = o.header.frame_id;
      newest = ToStamp(o.header.stamp);
      if (server.HasSubscribers(kOdometryChannel)) {
        server.Publish(kOdometryChannel, t, SharedBytes(OdometryCdr(o)));
      }
      if (server.HasSubscribers(kTfChannel)) server.Publish(kTfChannel, t, SharedBytes(TfCdr(o)));
    }, 64);
    clouds.TakeEach([&](const dammloam_msg_LabelledCloud& c, const dds_sample_info_t&) {
      try {
        const std::vector<ClassPoint> points = LabelledMapPoints(c, config.cloud_budget);
        map.Add(points);
        if (server.HasSubscribers(kLabelledCloudChannel)) {
          server.Publish(kLabelledCloudChannel, StampNanoseconds(c.header.stamp),
                         SharedBytes(ClassCloudCdr(points, ToStamp(c.header.stamp), map_frame)));
        }
      } catch (const std::invalid_argument& e) {
        ++counters.bad_samples;
        spdlog::warn("bridge: labelled cloud {} left out: {}", c.scan_index, e.what());
      }
    }, 4);
    loops.TakeEach([&](const dammloam_msg_LoopClosure& l, const dds_sample_info_t&) {
      if (!loop_lines.AddLoop(l)) return;
      server.Publish(kLoopClosureChannel, StampNanoseconds(l.header.stamp),
                     SharedBytes(loop_lines.MarkerArrayCdr(ToStamp(l.header.stamp), map_frame)));
    }, 64);
    status.TakeEach([&](const dammloam_msg_DaemonStatus& s, const dds_sample_info_t&) {
      const ServerStats stats = server.Stats();
      counters.clients = stats.clients;
      counters.frames_dropped = stats.frames_dropped;
      counters.map_points = map.size();
      server.Publish(kStatusChannel, StampNanoseconds(s.header.stamp),
                     SharedBytes(StatusJsonPayload(s, counters)));
    }, 4);

    if (Clock::now() >= next_map) {
      next_map = Clock::now() + map_period;
      const std::uint64_t t = StampNanoseconds(dammloam_msg_Time{newest.sec, newest.nanosec});
      // Whole, every period: a client that joins late gets all of it within one period.
      if (map.size() > 0 && server.HasSubscribers(kMapChannel)) {
        server.Publish(kMapChannel, t, SharedBytes(ClassCloudCdr(map.Points(), newest, map_frame)));
      }
      if (!trajectory.empty() && server.HasSubscribers(kTrajectoryChannel)) {
        server.Publish(kTrajectoryChannel, t, SharedBytes(trajectory.MarkerArrayCdr(newest, map_frame)));
      }
      // Also without new loops (an empty marker at first), so a client that joins late has them.
      if (!trajectory.empty() && server.HasSubscribers(kLoopClosureChannel)) {
        server.Publish(kLoopClosureChannel, t, SharedBytes(loop_lines.MarkerArrayCdr(newest, map_frame)));
      }
    }
  }
}

}  // namespace dammloam::bridge
