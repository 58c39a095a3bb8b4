// dammloam-replay: publishes a recording as PointCloud samples at the recorded rate, at X times
// speed, or in lock-step with dammloamd's Odometry. A sequence directory (or KITTI folder) with
// its imu.csv and wheel.csv, when present, as Imu and WheelOdometry samples; any other input
// dammloam-odometry reads (bags, MCAP, captures, cloud folders: tools/inputs) its scans only.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

#include "core/inertial/imu_horizon.hpp"
#include "core/inertial/wheel_horizon.hpp"
#include "tools/common/dds_tool_main.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/inertial_messages.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "io/sequence_io.hpp"
#include "io/sequence_meta.hpp"
#include "tools/inputs/scan_input.hpp"

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
  // Recordings other than sequence directories (tools/inputs/scan_input.hpp).
  tools::ScanInputOptions input;
  std::string write_sensor_meta;  // the model the scans were read with, for dammloamd --sensor-meta
};

// The sequence's IMU and wheel samples, and where publishing has got to. Each scan is preceded
// by every sample the odometry wants for it (IMU up to its end + 20 ms, wheels up to its end +
// 40 ms: core/inertial/imu_horizon.hpp, wheel_horizon.hpp) and the first sample of each stream
// past that, which tells dammloamd that the scan's samples are complete: in lock-step it then
// registers each scan with the samples dammloam-odometry would use (ahead of real time by up to
// one scan period). IMU stamps go out as imu.csv has them, on the IMU's
// clock, as a driver sends them: dammloamd subtracts the time offset (meta.json's
// imu.time_offset_s, given to it by --sensor-meta).
class InertialPublisher {
 public:
  InertialPublisher(dds::Participant& participant, const io::SequenceReader& sequence, const Options& o) {
    const io::SequenceMeta& meta = sequence.meta();
    io::StreamReadReport report;
    if (!o.no_imu) imu_ = sequence.ReadImu(&report);
    if (imu_) {
      time_offset_ = meta.imu_time_offset;
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

  // Skips the samples stamped before `t`, LiDAR clock (replay from a later scan).
  void SkipBefore(double t) {
    while (imu_ && next_imu_ < imu_->size() && (*imu_)[next_imu_].t - time_offset_ < t) ++next_imu_;
    while (wheel_ && next_wheel_ < wheel_->size() && (*wheel_)[next_wheel_].t < t) ++next_wheel_;
  }
  // Publishes every sample the scan starting at t_start wants (stamped at or before its
  // horizon, LiDAR clock), and the first sample of each stream after it.
  void PublishFor(double t_start, double period) {
    const double imu_horizon = ImuHorizon(t_start, period);
    for (bool past = false; imu_ && next_imu_ < imu_->size() && !past; ++next_imu_) {
      past = (*imu_)[next_imu_].t - time_offset_ > imu_horizon;
      imu_writer_->Write(dds::ToImuMessage((*imu_)[next_imu_], noise_, rate_, imu_frame_, next_imu_));
    }
    const double wheel_horizon = WheelHorizon(t_start, period);
    for (bool past = false; wheel_ && next_wheel_ < wheel_->size() && !past; ++next_wheel_) {
      past = (*wheel_)[next_wheel_].t > wheel_horizon;
      // The simulator's wheel noise (tools/simulate/wheel_model.hpp); real odometry brings its own.
      wheel_writer_->Write(
          dds::ToWheelMessage((*wheel_)[next_wheel_], 0.01, 0.005, base_frame_, next_wheel_));
    }
  }
  // A volatile sample written before a reader matched is lost: give subscribers of the
  // streams time to appear, once, after dammloamd's cloud reader did (dammloamd's IMU and wheel
  // readers are created with it).
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
  double time_offset_ = 0.0;  // imu.csv's stamps minus LiDAR time
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

// The DDS side of a replay: the cloud writer, and the Odometry reader lock-step waits on.
class CloudPublisher {
 public:
  CloudPublisher(dds::Participant& participant, const Options& o)
      : o_(o),
        points_topic_(participant, dammloam_msg_PointCloud_desc, o.topic, dds::PointsQos()),
        writer_(participant, points_topic_, dds::PointsQos()),
        odometry_topic_(participant, dammloam_msg_Odometry_desc, o.odometry_topic, dds::OdometryQos()),
        odometry_reader_(participant, odometry_topic_, dds::OdometryQos()),
        waitset_(participant) {
    waitset_.Attach(odometry_reader_);
  }

  // False (after an error) when dammloamd did not subscribe in time.
  bool WaitForDaemon() {
    const auto wait_ms = std::chrono::milliseconds(static_cast<int>(o_.wait_subscriber * 1000));
    if (!writer_.WaitForReaders(1, wait_ms)) {
      spdlog::error("no subscriber on topic '{}' (domain {}) after {} s: is dammloamd running with "
                    "the same CYCLONEDDS_URI and domain?", o_.topic, o_.domain, o_.wait_subscriber);
      return false;
    }
    if (o_.lockstep && odometry_reader_.MatchedWriters() == 0) {
      // The daemon's Odometry writer appears together with its PointCloud reader; give discovery
      // the same time budget.
      const auto deadline = Clock::now() + wait_ms;
      while (odometry_reader_.MatchedWriters() == 0 && Clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
    return true;
  }

  void Start(double first_time) {
    t0_ = Clock::now();
    first_time_ = first_time;
  }
  // At the scan's recorded instant (or after the last pose, lock-step): false after an error.
  // `before_write` runs just before the cloud goes out (the IMU and wheel samples that cover it).
  template <typename BeforeWrite>
  bool Publish(const Scan& scan, std::size_t index, BeforeWrite&& before_write) {
    const dds::CloudMessage cloud = dds::ScanToCloud(scan, o_.frame_id, index);
    if (!o_.lockstep) {
      const auto due = t0_ + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>((scan.t_start - first_time_) / o_.rate));
      std::this_thread::sleep_until(due);
    }
    before_write();
    writer_.Write(dds::CloudView(cloud).get());
    if (o_.lockstep && !WaitForPose(odometry_reader_, waitset_, cloud.stamp,
                                    std::chrono::duration<double>(o_.lockstep_timeout))) {
      spdlog::error("lock-step: no Odometry for scan {} (stamp {}.{:09d}) on '{}' within {} s; "
                    "did dammloamd reject it (see its Status) or stop?", index, cloud.stamp.sec,
                    cloud.stamp.nanosec, o_.odometry_topic, o_.lockstep_timeout);
      return false;
    }
    return true;
  }
  // Makes sure the last samples reached the subscribers before the participant goes away.
  void Finish(std::size_t published) const {
    dds_wait_for_acks(writer_.handle(), DDS_SECS(5));
    const double seconds = std::chrono::duration<double>(Clock::now() - t0_).count();
    spdlog::info("published {} scans in {:.2f} s", published, seconds);
  }
  std::string Pace() const {
    return o_.lockstep ? std::string("in lock-step") : fmt::format("at {}x", o_.rate);
  }

 private:
  const Options& o_;
  dds::Topic points_topic_;
  dds::Writer<dammloam_msg_PointCloud> writer_;
  dds::Topic odometry_topic_;
  dds::Reader<dammloam_msg_Odometry> odometry_reader_;
  dds::WaitSet waitset_;
  Clock::time_point t0_ = Clock::now();
  double first_time_ = 0.0;
};

int RunSequence(const Options& o) {
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
  if (!o.write_sensor_meta.empty()) io::WriteMeta(o.write_sensor_meta, sequence.meta());

  dds::Participant participant(static_cast<dds_domainid_t>(o.domain));
  CloudPublisher publisher(participant, o);
  InertialPublisher inertial(participant, sequence, o);
  const double period = sequence.meta().model.scan_period;
  inertial.SkipBefore(sequence.times()[o.start_index] - period);
  if (!publisher.WaitForDaemon()) return 3;
  inertial.WaitForReaders(std::chrono::milliseconds(1000));

  spdlog::info("replaying {} scans {}..{} of {} on '{}' (domain {}) {}", end - o.start_index,
               o.start_index, end - 1, o.sequence, o.topic, o.domain, publisher.Pace());
  publisher.Start(sequence.times()[o.start_index]);
  for (std::size_t k = o.start_index; k < end; ++k) {
    const Scan scan = sequence.ReadScan(k);
    // The first scan's samples are acknowledged before its cloud goes out: a reader that has
    // acknowledged has matched the writer, so dammloamd waits for the samples of its first scan
    // instead of registering it without them (its IMU reader may discover the writer later than
    // its cloud reader does; seen as a flaky lock-step test).
    const bool first = k == o.start_index;
    const auto samples = [&] {
      inertial.PublishFor(scan.t_start, period);
      if (first) inertial.WaitForAcks();
    };
    if (!publisher.Publish(scan, k, samples)) return 4;
  }
  inertial.WaitForAcks();
  publisher.Finish(end - o.start_index);
  return 0;
}

// Any other recording: its scans, read as they are published (a bag larger than memory streams).
int RunRecording(const Options& o, io::ScanSource& source) {
  const SensorModel& model = source.model();
  spdlog::info("{} ({}): {} rings, {} columns, {:.3f} s per scan; start dammloamd with a sensor "
               "of this model{}", o.sequence, source.kind(), model.rings, model.columns,
               model.scan_period,
               o.write_sensor_meta.empty() ? " (--write-sensor-meta FILE writes it as meta.json)"
                                           : ": --sensor-meta " + o.write_sensor_meta);
  if (!o.write_sensor_meta.empty()) {
    io::SequenceMeta meta;
    meta.sensor = source.kind();
    meta.model = model;
    io::WriteMeta(o.write_sensor_meta, meta);
  }
  for (std::size_t k = 0; k < o.start_index; ++k) {
    if (!source.Next()) {
      spdlog::error("--start-index {} is beyond the recording's {} scans", o.start_index, k);
      return 2;
    }
  }
  dds::Participant participant(static_cast<dds_domainid_t>(o.domain));
  CloudPublisher publisher(participant, o);
  if (!publisher.WaitForDaemon()) return 3;
  spdlog::info("replaying {} from scan {} on '{}' (domain {}) {}", o.sequence, o.start_index,
               o.topic, o.domain, publisher.Pace());
  std::size_t published = 0;
  for (std::size_t k = o.start_index; o.count == 0 || published < o.count; ++k) {
    std::optional<Scan> scan = source.Next();
    if (!scan) break;
    if (published == 0) publisher.Start(scan->t_start);
    if (!publisher.Publish(*scan, k, [] {})) return 4;
    ++published;
  }
  publisher.Finish(published);
  return 0;
}

int Run(Options o) {
  o.input.path = o.sequence;
  const bool sequence_directory = o.kitti || (std::filesystem::is_directory(o.sequence) &&
                                              std::filesystem::exists(std::filesystem::path(o.sequence) / "meta.json"));
  if (sequence_directory) return RunSequence(o);
  const std::unique_ptr<io::ScanSource> source = tools::OpenScanInput(o.input);
  if (source->kind() == "sequence") return RunSequence(o);
  return RunRecording(o, *source);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"dammloam-replay: publish a recording as dammloam PointCloud samples"};
  app.add_option("INPUT", o.sequence,
                 "sequence directory, KITTI folder, rosbag2 directory, .mcap, ROS 1 .bag, Ouster or "
                 "Velodyne .pcap, or a folder of .pcd/.ply files")
      ->required()->check(CLI::ExistingPath);
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
  app.add_option("--bag-topic", o.input.topic, "bags: the PointCloud2 (or packet) topic to read");
  app.add_option("--sensor-meta", o.input.sensor_meta, "bags, cloud folders: meta.json with the sensor model");
  app.add_option("--velodyne-model", o.input.velodyne_model, "raw Velodyne packets: vlp16, vlp32c, hdl32e, vls128");
  app.add_option("--velodyne-calibration", o.input.velodyne_calibration, "raw Velodyne packets: calibration YAML");
  app.add_option("--ouster-metadata", o.input.ouster_metadata, "Ouster .pcap: the sensor's metadata JSON");
  app.add_option("--scan-period", o.input.scan_period, "cloud folders: seconds between scans (default: from the names)");
  app.add_option("--write-sensor-meta", o.write_sensor_meta,
                 "write the sensor model the scans were read with as meta.json (dammloamd --sensor-meta)");
  app.add_flag("--allow-default-network", o.allow_default_network,
               "run without CYCLONEDDS_URI (uses the default network interface)");
  CLI11_PARSE(app, argc, argv);
  return tools::RunDdsTool(o.allow_default_network, [&] { return Run(o); });
}
