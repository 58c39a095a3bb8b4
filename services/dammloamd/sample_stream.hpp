#pragma once
// The DDS side of dammloamd's sample inputs (imu_input.hpp, wheel_input.hpp): the reader of the
// native topic and, with ros2, of the ROS 2 one, read as one timeline, and the wait before each
// scan until the stream has reached the scan's horizon. The inputs differ in how they check and
// hand over their samples, not in how they read and wait for them.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "services/dds/dds.hpp"
#include "services/dds/middleware_watch.hpp"

namespace dammloam::daemon {

// What the wait before one scan goes by (SampleStream::WaitForHorizon).
struct HorizonWait {
  double t_start;      // the scan's start, LiDAR clock
  double scan_period;  // s
  double horizon;      // every sample stamped at or before this is to be handed over first
  double max_wait;     // s
  bool first_scan;     // the first scan: wait even if no sample has come yet
};

template <typename NativeMessage, typename Ros2Message>
class SampleStream {
 public:
  SampleStream(const dds::Participant& participant, const dds_topic_descriptor_t& descriptor,
               const std::string& topic_name, const dds::TopicQos& qos)
      : topic_(participant, descriptor, topic_name, qos),
        reader_(participant, topic_, qos),
        waitset_(participant) {
    waitset_.Attach(reader_);
  }

  // With ros2: the ROS 2 topic's samples join the native topic's.
  void AddRos2(const dds::Participant& participant, const dds_topic_descriptor_t& descriptor,
               const std::string& topic_name, const dds::TopicQos& qos) {
    ros2_topic_.emplace(participant, descriptor, topic_name, qos);
    ros2_reader_.emplace(participant, *ros2_topic_, qos);
    waitset_.Attach(*ros2_reader_);
  }

  void Watch(dds::MiddlewareWatch& watch) const {
    watch.Watch(reader_);
    if (ros2_reader_) watch.Watch(*ros2_reader_);
  }

  // Hands every sample either reader holds to on_native / on_ros2; returns how many.
  template <typename OnNative, typename OnRos2>
  std::uint64_t TakeAll(OnNative&& on_native, OnRos2&& on_ros2) const {
    std::uint64_t taken = TakeEverything(reader_, on_native);
    // One timeline for both readers, as for the clouds.
    if (ros2_reader_) taken += TakeEverything(*ros2_reader_, on_ros2);
    return taken;
  }

  // Calls take() (which takes what arrived and moves last_t, the newest accepted stamp, on) and
  // waits for more until a sample at or past the horizon arrived: one writer sends in stamp
  // order, so every earlier one has come. No wait without a matched writer (nothing is coming),
  // nor while the stream is more than a scan behind the scans (stalled, or on another clock: its
  // samples are dropped), nor, after the first scan, while no usable sample has come at all (a
  // writer that sends nothing), so that a broken sensor does not cost every scan max_wait.
  // Returns whether max_wait ran out first.
  template <typename Take>
  bool WaitForHorizon(const HorizonWait& scan, const std::optional<double>& last_t,
                      const std::atomic<bool>& stop, Take&& take) const {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(scan.max_wait));
    while (true) {
      take();
      if ((last_t && *last_t >= scan.horizon) || stop || !WriterMatched()) return false;
      if (last_t ? *last_t < scan.t_start - scan.scan_period : !scan.first_scan) return false;
      const auto left = deadline - Clock::now();
      if (left <= Clock::duration::zero()) return true;
      // At most 10 ms: stop and the writers' matching are only looked at between waits.
      waitset_.Wait(std::clamp(std::chrono::ceil<std::chrono::milliseconds>(left),
                               std::chrono::milliseconds(1), std::chrono::milliseconds(10)));
    }
  }

 private:
  template <typename Message, typename OnSample>
  static std::uint64_t TakeEverything(const dds::Reader<Message>& reader, OnSample& on_sample) {
    std::uint64_t taken = 0;
    while (const int n = reader.TakeEach(
               [&](const Message& m, const dds_sample_info_t&) { on_sample(m); }, 64)) {
      taken += static_cast<std::uint64_t>(n);
    }
    return taken;
  }

  bool WriterMatched() const {
    return reader_.MatchedWriters() > 0 || (ros2_reader_ && ros2_reader_->MatchedWriters() > 0);
  }

  dds::Topic topic_;
  dds::Reader<NativeMessage> reader_;
  std::optional<dds::Topic> ros2_topic_;
  std::optional<dds::Reader<Ros2Message>> ros2_reader_;
  dds::WaitSet waitset_;
};

}  // namespace dammloam::daemon
