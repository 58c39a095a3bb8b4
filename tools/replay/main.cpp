// dammloam-replay: publishes a sequence directory (or KITTI folder) as PointCloud samples at the
// recorded rate, at X times speed, or in lock-step with dammloamd's Odometry; the sequence's
// imu.csv and wheel.csv, when present, as Imu and WheelOdometry samples.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

#include "tools/common/dds_tool_main.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/inertial_messages.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "io/sequence_io.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace dammloam;

struct Options {
  std::string sequence;
  std::uint32_t domain = 0;
  double rate = 1.0;
  bool lockstep = false;
  std::string topic = dds::TopicNames{}.points;
  std::string odometry_topic = dds::TopicNames{}.odometry;
  std::size_t start_index = 0;
  std::size_t count = 0;  // 0 = all
  std::string frame_id = "lidar";
  bool kitti = false;
  double lockstep_timeout = 10.0;
  double wait_subscriber = 10.0;
  bool allow_default_network = false;
  bool no_imu = false, no_wheel = false;
  std::string imu_topic = dds::TopicNames{}.imu;
  std::string wheel_topic = dds::TopicNames{}.wheel_odometry;
  std::string imu_frame_id = "imu", base_frame_id = "base";
};

// The sequence's IMU and wheel samples, on the LiDAR clock, and where publishing has got to.
// Each scan is preceded by every sample up to its end, so a receiver has the motion that
// covers a scan when the scan arrives (ahead of real time by up to one scan period).
class InertialPublisher {
 public:
  InertialPublisher(dds::Participant& participant, const io::SequenceReader& sequence, const Options& o) {
    const io::SequenceMeta& meta = sequence.meta();
    io::StreamReadReport report;
    if (!o.no_imu) imu_ = sequence.ReadImu(&report);
    if (imu_) {
      for (ImuSample& s : *imu_) s.t -= meta.imu_time_offset;
      noise_ = meta.imu_noise.value_or(ImuNoise{});
      if (imu_->size() > 1) rate_ = static_cast<double>(imu_->size() - 1) / (imu_->back().t - imu_->front().t);
      imu_topic_.emplace(participant, dammloam_msg_Imu_desc, o.imu_topic, dds::ImuQos());
      imu_writer_.emplace(participant, *imu_topic_, dds::ImuQos());
      spdlog::info("imu.csv: {} samples ({:.0f} Hz) on '{}'{}", imu_->size(), rate_, o.imu_topic,
                   report.dropped() ? "; " + report.Summary() : std::string());
    }
    if (!o.no_wheel) wheel_ = sequence.ReadWheel(&report);
    if (wheel_) {
      wheel_topic_.emplace(participant, dammloam_msg_WheelOdometry_desc, o.wheel_topic, dds::WheelOdometryQos());
      wheel_writer_.emplace(participant, *wheel_topic_, dds::WheelOdometryQos());
      spdlog::info("wheel.csv: {} samples on '{}'{}", wheel_->size(), o.wheel_topic,
                   report.dropped() ? "; " + report.Summary() : std::string());
    }
    imu_frame_ = o.imu_frame_id;
    base_frame_ = o.base_frame_id;
  }

  // Skips the samples more than one period before `t` (replay from a later scan).
  void SkipBefore(double t) {
    while (imu_ && next_imu_ < imu_->size() && (*imu_)[next_imu_].t < t) ++next_imu_;
    while (wheel_ && next_wheel_ < wheel_->size() && (*wheel_)[next_wheel_].t < t) ++next_wheel_;
  }
  // Publishes every sample stamped before `t`.
  void PublishUntil(double t) {
    for (; imu_ && next_imu_ < imu_->size() && (*imu_)[next_imu_].t < t; ++next_imu_) {
      imu_writer_->Write(dds::ToImuMessage((*imu_)[next_imu_], noise_, rate_, imu_frame_, next_imu_));
    }
    for (; wheel_ && next_wheel_ < wheel_->size() && (*wheel_)[next_wheel_].t < t; ++next_wheel_) {
      // The simulator's wheel noise (tools/simulate/wheel_model.hpp); real odometry brings its own.
      wheel_writer_->Write(
          dds::ToWheelMessage((*wheel_)[next_wheel_], 0.01, 0.005, base_frame_, next_wheel_));
    }
  }
  // A volatile sample written before a reader matched is lost: give subscribers of the
  // streams time to appear, once, after dammloamd's cloud reader did (dammloamd itself does
  // not subscribe to them yet, so this does not wait for it).
  void WaitForReaders(std::chrono::milliseconds timeout) const {
    if (imu_writer_ && !imu_writer_->WaitForReaders(1, timeout)) {
      spdlog::info("no subscriber on '{}' yet: publishing the IMU samples anyway", imu_writer_->topic_name());
    }
    if (wheel_writer_ && !wheel_writer_->WaitForReaders(1, timeout)) {
      spdlog::info("no subscriber on '{}' yet: publishing the wheel odometry anyway", wheel_writer_->topic_name());
    }
  }
  void WaitForAcks() const {
    if (imu_writer_) dds_wait_for_acks(imu_writer_->handle(), DDS_SECS(5));
    if (wheel_writer_) dds_wait_for_acks(wheel_writer_->handle(), DDS_SECS(5));
  }

 private:
  std::optional<std::vector<ImuSample>> imu_;
  std::optional<std::vector<WheelSample>> wheel_;
  ImuNoise noise_;
  double rate_ = 100.0;
  std::string imu_frame_, base_frame_;
  std::optional<dds::Topic> imu_topic_, wheel_topic_;
  std::optional<dds::Writer<dammloam_msg_Imu>> imu_writer_;
  std::optional<dds::Writer<dammloam_msg_WheelOdometry>> wheel_writer_;
  std::size_t next_imu_ = 0, next_wheel_ = 0;
};

bool SameStamp(const dammloam_msg_Time& a, const dammloam_msg_Time& b) {
  return a.sec == b.sec && a.nanosec == b.nanosec;
}

// Waits until dammloamd published the Odometry of the scan stamped `stamp`.
bool WaitForPose(const dds::Reader<dammloam_msg_Odometry>& reader, const dds::WaitSet& waitset,
                 const dammloam_msg_Time& stamp, std::chrono::duration<double> timeout) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(timeout);
  bool found = false;
  while (!found && Clock::now() < deadline) {
    waitset.Wait(std::chrono::milliseconds(50));
    reader.TakeEach([&](const dammloam_msg_Odometry& odom, const dds_sample_info_t&) {
      if (SameStamp(odom.header.stamp, stamp)) found = true;
    });
  }
  return found;
}

int Run(const Options& o) {
  io::ReadOptions read_options;
  if (o.kitti) read_options.layout = io::PointLayout::kXYZI;
  const io::SequenceReader sequence = io::SequenceReader::Open(o.sequence, read_options);
  if (o.start_index >= sequence.size()) {
    spdlog::error("--start-index {} is beyond the sequence's {} scans", o.start_index,
                  sequence.size());
    return 2;
  }
  const std::size_t end =
      o.count == 0 ? sequence.size() : std::min(sequence.size(), o.start_index + o.count);

  dds::Participant participant(static_cast<dds_domainid_t>(o.domain));
  dds::Topic points_topic(participant, dammloam_msg_PointCloud_desc, o.topic, dds::PointsQos());
  dds::Writer<dammloam_msg_PointCloud> writer(participant, points_topic, dds::PointsQos());
  dds::Topic odometry_topic(participant, dammloam_msg_Odometry_desc, o.odometry_topic,
                            dds::OdometryQos());
  dds::Reader<dammloam_msg_Odometry> odometry_reader(participant, odometry_topic,
                                                     dds::OdometryQos());
  dds::WaitSet waitset(participant);
  waitset.Attach(odometry_reader);
  InertialPublisher inertial(participant, sequence, o);
  const double period = sequence.meta().model.scan_period;
  inertial.SkipBefore(sequence.times()[o.start_index] - period);

  const auto wait_ms = std::chrono::milliseconds(static_cast<int>(o.wait_subscriber * 1000));
  if (!writer.WaitForReaders(1, wait_ms)) {
    spdlog::error("no subscriber on topic '{}' (domain {}) after {} s: is dammloamd running with "
                  "the same CYCLONEDDS_URI and domain?", o.topic, o.domain, o.wait_subscriber);
    return 3;
  }
  inertial.WaitForReaders(std::chrono::milliseconds(1000));
  if (o.lockstep && odometry_reader.MatchedWriters() == 0) {
    // The daemon's Odometry writer appears together with its PointCloud reader; give discovery
    // the same time budget.
    const auto deadline = Clock::now() + wait_ms;
    while (odometry_reader.MatchedWriters() == 0 && Clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  spdlog::info("replaying {} scans {}..{} of {} on '{}' (domain {}) {}", end - o.start_index,
               o.start_index, end - 1, o.sequence, o.topic, o.domain,
               o.lockstep ? std::string("in lock-step") : fmt::format("at {}x", o.rate));
  const auto t0 = Clock::now();
  const double first_time = sequence.times()[o.start_index];
  for (std::size_t k = o.start_index; k < end; ++k) {
    const Scan scan = sequence.ReadScan(k);
    const dds::CloudMessage cloud = dds::ScanToCloud(scan, o.frame_id, k);
    if (!o.lockstep) {
      const auto due = t0 + std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double>((scan.t_start - first_time) / o.rate));
      std::this_thread::sleep_until(due);
    }
    inertial.PublishUntil(scan.t_start + period);
    writer.Write(dds::CloudView(cloud).get());
    if (o.lockstep &&
        !WaitForPose(odometry_reader, waitset, cloud.stamp,
                     std::chrono::duration<double>(o.lockstep_timeout))) {
      spdlog::error("lock-step: no Odometry for scan {} (stamp {}.{:09d}) on '{}' within {} s; "
                    "did dammloamd reject it (see its Status) or stop?", k, cloud.stamp.sec,
                    cloud.stamp.nanosec, o.odometry_topic, o.lockstep_timeout);
      return 4;
    }
  }
  // Make sure the last samples reached the subscribers before the participant goes away.
  dds_wait_for_acks(writer.handle(), DDS_SECS(5));
  inertial.WaitForAcks();
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  spdlog::info("published {} scans in {:.2f} s", end - o.start_index, seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"dammloam-replay: publish a sequence directory as dammloam PointCloud samples"};
  app.add_option("SEQUENCE_DIR", o.sequence, "sequence directory or KITTI folder")
      ->required()->check(CLI::ExistingDirectory);
  app.add_option("--domain", o.domain, "DDS domain id");
  auto* rate = app.add_option("--rate", o.rate, "speed factor over the recorded rate")
                   ->check(CLI::PositiveNumber);
  app.add_flag("--lockstep", o.lockstep, "send scan k+1 only after the Odometry of scan k")
      ->excludes(rate);
  app.add_option("--topic", o.topic, "PointCloud topic");
  app.add_option("--odometry-topic", o.odometry_topic, "Odometry topic (lock-step)");
  app.add_option("--start-index", o.start_index, "first scan to publish");
  app.add_option("--count", o.count, "number of scans (0 = to the end)");
  app.add_option("--frame-id", o.frame_id, "header.frame_id of the clouds");
  app.add_flag("--kitti", o.kitti, "KITTI layout (x y z intensity, no time/ring)");
  app.add_option("--lockstep-timeout", o.lockstep_timeout, "seconds to wait for each pose")
      ->check(CLI::PositiveNumber);
  app.add_option("--wait-subscriber", o.wait_subscriber, "seconds to wait for dammloamd")
      ->check(CLI::PositiveNumber);
  app.add_flag("--no-imu", o.no_imu, "do not publish the sequence's imu.csv");
  app.add_flag("--no-wheel", o.no_wheel, "do not publish the sequence's wheel.csv");
  app.add_option("--imu-topic", o.imu_topic, "Imu topic");
  app.add_option("--wheel-topic", o.wheel_topic, "WheelOdometry topic");
  app.add_flag("--allow-default-network", o.allow_default_network,
               "run without CYCLONEDDS_URI (uses the default network interface)");
  CLI11_PARSE(app, argc, argv);
  return tools::RunDdsTool(o.allow_default_network, [&] { return Run(o); });
}
