#pragma once
// Test-side DDS peer of dammloamd: publishes clouds, collects Odometry, Status and
// LabelledCloud samples (copied out of the loans) and waits for specific ones.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "services/dds/dds.hpp"
#include "services/dds/messages.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::test {

// Pins Cyclone DDS to loopback for this process and the processes it starts.
inline void UseLoopbackDds() {
  const char* uri = std::getenv("CYCLONEDDS_URI");
  if (uri == nullptr || *uri == '\0') {
    // Appended, not concatenated: GCC 12 at -O1 warned (-Warray-bounds) on the inlined
    // concatenation of the literal with the macro's string, a false positive.
    std::string file = "file://";
    file += (std::filesystem::path(DAMMLOAM_SOURCE_DIR) / "deploy/cyclonedds-loopback.xml").string();
    setenv("CYCLONEDDS_URI", file.c_str(), 1);
  }
}

struct ReceivedPose {
  dammloam_msg_Time stamp{};
  std::uint64_t input_seq = 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  bool registered = false;
  std::string status;
  std::string tracking;
  std::string point_times;
};

struct ReceivedStatus {
  bool is_error_event = false;
  std::uint8_t state = 0;
  std::string last_error;
  std::uint64_t received = 0, processed = 0, dropped = 0, rejected = 0;
  std::uint64_t commands_refused = 0;
  std::map<std::string, std::uint64_t> refused_by_reason;
  std::uint64_t receive_errors = 0, publish_errors = 0, backend_errors = 0;
  std::string loop_closure;
  std::uint64_t samples_lost = 0, samples_rejected = 0, samples_undeserializable = 0,
                incompatible_qos = 0;
  std::map<std::string, std::uint64_t> middleware_by_reason;
  std::string tracking;
  std::uint64_t degraded = 0, lost = 0, without_point_times = 0;
  std::uint64_t imu_samples = 0, imu_samples_dropped = 0, scans_with_imu = 0, scans_without_imu = 0;
  std::map<std::string, std::uint64_t> imu_by_reason;
  std::uint64_t wheel_samples = 0, wheel_samples_dropped = 0, scans_with_wheel = 0,
                scans_without_wheel = 0;
  std::map<std::string, std::uint64_t> wheel_by_reason;
  std::uint64_t scans_with_accelerometer = 0, scans_without_accelerometer = 0;
  std::map<std::string, std::uint64_t> accelerometer_by_reason;
  std::uint64_t labelled_clouds_published = 0, labelled_clouds_skipped = 0;
};

inline ReceivedStatus CopyStatus(const dammloam_msg_DaemonStatus& m) {
  ReceivedStatus s{m.is_error_event, m.state, m.last_error, m.scans_received, m.scans_processed,
                   m.scans_dropped, m.scans_rejected, m.commands_refused, {}, m.receive_errors,
                   m.publish_errors, m.backend_errors, m.loop_closure, m.samples_lost,
                   m.samples_rejected, m.samples_undeserializable, m.incompatible_qos, {},
                   m.tracking, m.scans_degraded, m.scans_lost, m.scans_without_point_times,
                   m.imu_samples, m.imu_samples_dropped, m.scans_with_imu, m.scans_without_imu, {},
                   m.wheel_samples, m.wheel_samples_dropped, m.scans_with_wheel,
                   m.scans_without_wheel, {}, m.scans_with_accelerometer,
                   m.scans_without_accelerometer, {}, m.labelled_clouds_published,
                   m.labelled_clouds_skipped};
  for (std::uint32_t i = 0; i < m.imu_by_reason._length; ++i) {
    s.imu_by_reason[m.imu_by_reason._buffer[i].reason] = m.imu_by_reason._buffer[i].count;
  }
  for (std::uint32_t i = 0; i < m.wheel_by_reason._length; ++i) {
    s.wheel_by_reason[m.wheel_by_reason._buffer[i].reason] = m.wheel_by_reason._buffer[i].count;
  }
  for (std::uint32_t i = 0; i < m.accelerometer_by_reason._length; ++i) {
    const auto& r = m.accelerometer_by_reason._buffer[i];
    s.accelerometer_by_reason[r.reason] = r.count;
  }
  for (std::uint32_t i = 0; i < m.refused_by_reason._length; ++i) {
    s.refused_by_reason[m.refused_by_reason._buffer[i].reason] = m.refused_by_reason._buffer[i].count;
  }
  for (std::uint32_t i = 0; i < m.middleware_by_reason._length; ++i) {
    const auto& r = m.middleware_by_reason._buffer[i];
    s.middleware_by_reason[r.reason] = r.count;
  }
  return s;
}

struct ReceivedLabelledCloud {
  dammloam_msg_Time stamp{};
  std::size_t width = 0;
  std::string error;                 // conversion problem, empty if none
  std::vector<PointClass> labels;
  std::vector<std::uint8_t> raw_labels;
};

inline bool SameStamp(const dammloam_msg_Time& a, const dammloam_msg_Time& b) {
  return a.sec == b.sec && a.nanosec == b.nanosec;
}

class DdsTestClient {
 public:
  explicit DdsTestClient(std::uint32_t domain, const dds::TopicNames& topics = {})
      : participant_(static_cast<dds_domainid_t>(domain)),
        points_topic_(participant_, dammloam_msg_PointCloud_desc, topics.points, dds::PointsQos()),
        odometry_topic_(participant_, dammloam_msg_Odometry_desc, topics.odometry,
                        dds::OdometryQos()),
        status_topic_(participant_, dammloam_msg_DaemonStatus_desc, topics.status,
                      dds::StatusQos()),
        labelled_topic_(participant_, dammloam_msg_LabelledCloud_desc, topics.labelled_cloud,
                        dds::LabelledCloudQos()),
        points_(participant_, points_topic_, dds::PointsQos(16)),  // bursts reach the daemon whole
        odometry_(participant_, odometry_topic_, {true, 1000, true}),
        status_(participant_, status_topic_, {true, 1000, true}),
        labelled_(participant_, labelled_topic_, {true, 100, false}) {}

  // Waits until the daemon's reader and writers are matched.
  bool WaitForDaemon(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (points_.MatchedReaders() > 0 && odometry_.MatchedWriters() > 0 &&
          status_.MatchedWriters() > 0 && labelled_.MatchedWriters() > 0) {
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  void Publish(const dds::CloudMessage& cloud) { points_.Write(dds::CloudView(cloud).get()); }

  void Poll() {
    odometry_.TakeEach([this](const dammloam_msg_Odometry& m, const dds_sample_info_t&) {
      poses.push_back({m.header.stamp, m.input_seq, dds::FromMsgPose(m.pose), m.registered,
                       m.status, m.tracking, m.point_times});
    }, 64);
    status_.TakeEach([this](const dammloam_msg_DaemonStatus& m, const dds_sample_info_t&) {
      statuses.push_back(CopyStatus(m));
    }, 64);
    labelled_.TakeEach([this](const dammloam_msg_LabelledCloud& m, const dds_sample_info_t&) {
      ReceivedLabelledCloud c;
      c.stamp = m.header.stamp;
      c.width = std::size_t{m.cloud.width} * m.cloud.height;
      if (auto points = dds::CloudToLabelled(m.cloud, &c.error)) c.labels = points->labels;
      for (std::uint32_t i = 0; i < m.cloud.data._length; i += m.cloud.point_step) {
        c.raw_labels.push_back(m.cloud.data._buffer[i + 36]);
      }
      clouds.push_back(std::move(c));
    }, 16);
  }

  // Polls until pred() holds or the timeout passes.
  bool WaitUntil(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      Poll();
      if (pred()) return true;
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  std::size_t CountPoses(const dammloam_msg_Time& stamp) const {
    std::size_t n = 0;
    for (const auto& p : poses) n += SameStamp(p.stamp, stamp) ? 1 : 0;
    return n;
  }

  bool WaitForPose(const dammloam_msg_Time& stamp, std::chrono::milliseconds timeout) {
    return WaitUntil([&] { return CountPoses(stamp) > 0; }, timeout);
  }

  // Waits for an error Status whose last_error contains `text`; returns that message.
  std::optional<std::string> WaitForError(const std::string& text,
                                          std::chrono::milliseconds timeout) {
    std::optional<std::string> found;
    WaitUntil([&] {
      for (const auto& s : statuses) {
        if (s.is_error_event && s.last_error.find(text) != std::string::npos) {
          found = s.last_error;
          return true;
        }
      }
      return false;
    }, timeout);
    return found;
  }

  std::vector<ReceivedPose> poses;
  std::vector<ReceivedStatus> statuses;
  std::vector<ReceivedLabelledCloud> clouds;

 private:
  dds::Participant participant_;
  dds::Topic points_topic_, odometry_topic_, status_topic_, labelled_topic_;
  dds::Writer<dammloam_msg_PointCloud> points_;
  dds::Reader<dammloam_msg_Odometry> odometry_;
  dds::Reader<dammloam_msg_DaemonStatus> status_;
  dds::Reader<dammloam_msg_LabelledCloud> labelled_;
};

}  // namespace dammloam::test
