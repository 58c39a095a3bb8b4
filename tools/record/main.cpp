// dammloam-record: subscribes to dammloamd's topics and writes poses (TUM), loop-closure and
// status events (JSON lines) and optionally the labelled clouds (PCD).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include "tools/common/dds_tool_main.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/messages.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "io/pcd/labelled_pcd.hpp"
#include "io/tum.hpp"
#include "tools/record/mcap_recording.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace dammloam;

std::atomic<bool> g_stop{false};
extern "C" void OnSignal(int) { g_stop = true; }

struct Options {
  std::string poses;
  std::string events;
  std::string clouds;
  std::string mcap;
  std::uint32_t domain = 0;
  std::size_t count = 0;  // 0 = unlimited
  double timeout = 10.0;
  bool clouds_in_map_frame = false;
  dds::TopicNames topics;
  bool allow_default_network = false;
};

std::string Stamp(const dammloam_msg_Time& t) {
  return fmt::format("{}.{:09d}", t.sec, t.nanosec);
}

nlohmann::json ReasonsJson(const dds_sequence_dammloam_msg_ReasonCount& counts) {
  nlohmann::json reasons = nlohmann::json::object();
  for (std::uint32_t i = 0; i < counts._length; ++i) {
    reasons[counts._buffer[i].reason] = counts._buffer[i].count;
  }
  return reasons;
}

nlohmann::json StatusJson(const dammloam_msg_DaemonStatus& s) {
  const nlohmann::json reasons = ReasonsJson(s.rejected_by_reason);
  return {{"type", "status"}, {"stamp", Stamp(s.header.stamp)}, {"node", s.node},
          {"state", s.state}, {"received", s.scans_received}, {"processed", s.scans_processed},
          {"dropped", s.scans_dropped}, {"rejected", s.scans_rejected}, {"reasons", reasons},
          {"latency_median_ms", s.latency_median_ms}, {"latency_p95_ms", s.latency_p95_ms},
          {"latency_p99_ms", s.latency_p99_ms}, {"latency_max_ms", s.latency_max_ms},
          {"error_count", s.error_count}, {"last_error", s.last_error},
          {"is_error_event", s.is_error_event}, {"commands_refused", s.commands_refused},
          {"refused_by_reason", ReasonsJson(s.refused_by_reason)},
          {"receive_errors", s.receive_errors}, {"publish_errors", s.publish_errors},
          {"backend_errors", s.backend_errors}, {"loop_closure", s.loop_closure},
          {"samples_lost", s.samples_lost}, {"samples_rejected", s.samples_rejected},
          {"samples_undeserializable", s.samples_undeserializable},
          {"incompatible_qos", s.incompatible_qos},
          {"middleware_by_reason", ReasonsJson(s.middleware_by_reason)},
          {"tracking", s.tracking}, {"scans_degraded", s.scans_degraded},
          {"scans_lost", s.scans_lost}, {"imu_samples", s.imu_samples},
          {"imu_samples_dropped", s.imu_samples_dropped}, {"scans_with_imu", s.scans_with_imu},
          {"scans_without_imu", s.scans_without_imu},
          {"imu_by_reason", ReasonsJson(s.imu_by_reason)}, {"wheel_samples", s.wheel_samples},
          {"wheel_samples_dropped", s.wheel_samples_dropped},
          {"scans_with_wheel", s.scans_with_wheel}, {"scans_without_wheel", s.scans_without_wheel},
          {"wheel_by_reason", ReasonsJson(s.wheel_by_reason)},
          {"scans_with_accelerometer", s.scans_with_accelerometer},
          {"scans_without_accelerometer", s.scans_without_accelerometer},
          {"accelerometer_by_reason", ReasonsJson(s.accelerometer_by_reason)},
          {"labelled_clouds_published", s.labelled_clouds_published},
          {"labelled_clouds_skipped", s.labelled_clouds_skipped}};
}

nlohmann::json LoopJson(const dammloam_msg_LoopClosure& l) {
  const auto& p = l.relative_pose;
  return {{"type", "loop_closure"}, {"stamp", Stamp(l.header.stamp)},
          {"query_keyframe", l.query_keyframe}, {"match_keyframe", l.match_keyframe},
          {"query_stamp", Stamp(l.query_stamp)}, {"match_stamp", Stamp(l.match_stamp)},
          {"relative_pose", {p.position.x, p.position.y, p.position.z, p.orientation.x,
                             p.orientation.y, p.orientation.z, p.orientation.w}},
          {"score", l.score}, {"accepted", l.accepted}, {"reason", l.reason}};
}

void WriteCloud(const Options& o, const dammloam_msg_LabelledCloud& msg) {
  std::string error;
  const auto points = dds::CloudToLabelled(msg.cloud, &error);
  if (!points) {
    spdlog::warn("labelled cloud {}: {}", Stamp(msg.header.stamp), error);
    return;
  }
  io::LabelledCloud cloud;
  cloud.points = o.clouds_in_map_frame ? points->points_map : points->points_sensor;
  cloud.labels = points->labels;
  for (const auto& n : points->normals) cloud.normals.push_back(n.cast<double>());
  io::WriteLabelledPcd(std::filesystem::path(o.clouds) / (Stamp(msg.header.stamp) + ".pcd"),
                       cloud);
}

int Run(const Options& o) {
  dds::Participant participant(static_cast<dds_domainid_t>(o.domain));
  dds::Topic odometry_topic(participant, dammloam_msg_Odometry_desc, o.topics.odometry,
                            dds::OdometryQos());
  dds::Topic status_topic(participant, dammloam_msg_DaemonStatus_desc, o.topics.status,
                          dds::StatusQos());
  dds::Topic loop_topic(participant, dammloam_msg_LoopClosure_desc, o.topics.loop_closure,
                        dds::LoopClosureQos());
  // A deep history so no pose is lost while this thread writes files.
  dds::Reader<dammloam_msg_Odometry> odometry(participant, odometry_topic, {true, 1000, true});
  dds::Reader<dammloam_msg_DaemonStatus> status(participant, status_topic, dds::StatusQos(16));
  dds::Reader<dammloam_msg_LoopClosure> loops(participant, loop_topic, dds::LoopClosureQos());
  dds::WaitSet waitset(participant);
  waitset.Attach(odometry);
  waitset.Attach(loops);
  if (!o.events.empty() || !o.mcap.empty()) waitset.Attach(status);
  std::optional<tools::McapRecording> mcap;
  if (!o.mcap.empty()) mcap.emplace(o.mcap);
  std::optional<dds::Topic> cloud_topic;
  std::optional<dds::Reader<dammloam_msg_LabelledCloud>> clouds;
  if (!o.clouds.empty() || mcap) {
    if (!o.clouds.empty()) std::filesystem::create_directories(o.clouds);
    cloud_topic.emplace(participant, dammloam_msg_LabelledCloud_desc, o.topics.labelled_cloud,
                        dds::LabelledCloudQos());
    clouds.emplace(participant, *cloud_topic, dds::TopicQos{true, 8, false});
    waitset.Attach(*clouds);
  }
  std::ofstream events;
  if (!o.events.empty()) {
    events.open(o.events);
    if (!events) throw std::runtime_error("cannot write " + o.events);
  }

  std::vector<io::StampedPose> poses;
  std::set<std::tuple<std::int32_t, std::uint32_t>> seen;  // latched poses may come twice
  auto last_data = Clock::now();
  const auto timeout = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(o.timeout));
  spdlog::info("recording '{}' on domain {} until {} poses or {} s without data",
               o.topics.odometry, o.domain, o.count == 0 ? "unlimited" : std::to_string(o.count),
               o.timeout);
  // Everything waiting on the readers; poses beyond --count are not kept.
  const auto take = [&] {
    odometry.TakeEach([&](const dammloam_msg_Odometry& m, const dds_sample_info_t&) {
      last_data = Clock::now();
      if (!seen.insert({m.header.stamp.sec, m.header.stamp.nanosec}).second) return;
      if (o.count != 0 && poses.size() >= o.count) return;
      poses.push_back({dds::ToSeconds(m.header.stamp), dds::FromMsgPose(m.pose)});
      if (mcap) mcap->AddOdometry(m);
    }, 64);
    loops.TakeEach([&](const dammloam_msg_LoopClosure& m, const dds_sample_info_t&) {
      last_data = Clock::now();
      if (events.is_open()) events << LoopJson(m).dump() << '\n' << std::flush;
      if (mcap) mcap->AddLoop(m);
    });
    if (events.is_open() || mcap) {
      status.TakeEach([&](const dammloam_msg_DaemonStatus& m, const dds_sample_info_t&) {
        const std::string line = StatusJson(m).dump();
        if (events.is_open()) events << line << '\n' << std::flush;
        if (mcap) mcap->AddStatus(m.header.stamp, line);
      });
    }
    if (clouds) {
      clouds->TakeEach([&](const dammloam_msg_LabelledCloud& m, const dds_sample_info_t&) {
        last_data = Clock::now();
        if (!o.clouds.empty()) WriteCloud(o, m);
        std::string error;
        if (mcap && !mcap->AddLabelledCloud(m, &error)) {
          spdlog::warn("labelled cloud {}: {}", Stamp(m.header.stamp), error);
        }
      });
    }
  };
  while (!g_stop && (o.count == 0 || poses.size() < o.count) &&
         Clock::now() - last_data < timeout) {
    waitset.Wait(std::chrono::milliseconds(50));
    take();
  }
  // The labelled cloud and the loop events of the last pose are published just after it: wait
  // a moment for them, so a --count run holds every cloud of its poses.
  if (!g_stop && o.count != 0 && poses.size() >= o.count) {
    const auto until = Clock::now() + std::chrono::milliseconds(300);
    while (Clock::now() < until) {
      waitset.Wait(std::chrono::milliseconds(50));
      take();
    }
  }
  // Poses come in stamp order from one daemon; sort anyway so the TUM file is always valid.
  std::sort(poses.begin(), poses.end(),
            [](const io::StampedPose& a, const io::StampedPose& b) { return a.t < b.t; });
  io::WriteTum(o.poses, poses);
  if (mcap) mcap->Close();
  spdlog::info("wrote {} poses to {}{}{}", poses.size(), o.poses, mcap ? " and " + o.mcap : "",
               g_stop ? " (stopped by signal)" : "");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"dammloam-record: write dammloamd's poses, events and clouds to files"};
  app.add_option("--poses", o.poses, "output TUM trajectory")->required();
  app.add_option("--events", o.events, "output JSON lines: loop closures and status");
  app.add_option("--clouds", o.clouds, "output directory for labelled clouds (PCD)");
  app.add_flag("--clouds-in-map-frame", o.clouds_in_map_frame, "write map-frame coordinates");
  app.add_option("--mcap", o.mcap,
                 "also write everything as ROS 2 messages into this MCAP (odometry, /tf, labelled "
                 "clouds, loop closures, status) for Foxglove, Lichtblick or ros2 bag play");
  app.add_option("--domain", o.domain, "DDS domain id");
  app.add_option("--count", o.count, "exit after this many poses (0 = no limit)");
  app.add_option("--timeout", o.timeout, "exit after this many seconds without data")
      ->check(CLI::PositiveNumber);
  app.add_option("--odometry-topic", o.topics.odometry, "Odometry topic");
  app.add_option("--status-topic", o.topics.status, "Status topic");
  app.add_option("--loop-closure-topic", o.topics.loop_closure, "LoopClosure topic");
  app.add_option("--labelled-cloud-topic", o.topics.labelled_cloud, "LabelledCloud topic");
  app.add_flag("--allow-default-network", o.allow_default_network,
               "run without CYCLONEDDS_URI (uses the default network interface)");
  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  return tools::RunDdsTool(o.allow_default_network, [&] { return Run(o); });
}
