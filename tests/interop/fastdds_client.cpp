// dammloam-interop-fastdds: drives dammloamd from an eProsima Fast DDS participant, so that the
// daemon (Cyclone DDS) is tested against a second DDS vendor. Publishes a sequence directory in
// lock-step (scan k+1 only after the pose of scan k arrived; a scan whose pose is late is
// published again, see --resend-after) and writes the poses as TUM.
//   --mode native: dammloam::msg::PointCloud on dammloam_points (the replay tool's layout),
//                  dammloam::msg::Odometry from dammloam_odometry;
//   --mode ros2:   sensor_msgs::msg::dds_::PointCloud2_ on rt/points (ouster-ros point layout,
//                  ROS 2 sensor-data QoS), nav_msgs::msg::dds_::Odometry_ from
//                  rt/dammloam/odometry (reliable, keep-last 10).
// The participant only ever uses UDPv4 on 127.0.0.1 with unicast discovery (no shared memory,
// no multicast), the counterpart of deploy/cyclonedds-loopback.xml.
// Exit codes: 0 every pose arrived, 2 bad arguments or sequence, 3 no daemon, 4 a pose missing.
#include <CLI/CLI.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "io/sequence_io.hpp"
#include "io/tum.hpp"
#include "native/dammloamPubSubTypes.h"
#include "ros2/nav_msgsPubSubTypes.h"
#include "ros2/sensor_msgsPubSubTypes.h"

namespace {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string sequence;
  std::string mode = "native";
  std::uint32_t domain = 0;
  std::string out;
  std::string points_topic;    // default depends on the mode
  std::string odometry_topic;  // default depends on the mode
  std::string frame_id = "lidar";
  double wait_daemon = 30.0;
  double pose_timeout = 60.0;
  double resend_after = 1.0;   // republish a scan whose pose is this late (seconds)
};

// builtin_interfaces/Time as dammloam's services/dds/point_cloud.cpp computes it (ToMsgTime), so
// that both vendors' runs stamp every scan identically.
struct Stamp {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  bool operator==(const Stamp&) const = default;
};

Stamp ToStamp(double seconds) {
  double whole = std::floor(seconds);
  auto nanosec = static_cast<std::int64_t>(std::llround((seconds - whole) * 1e9));
  if (nanosec >= 1000000000) {
    whole += 1.0;
    nanosec -= 1000000000;
  }
  return {static_cast<std::int32_t>(whole), static_cast<std::uint32_t>(nanosec)};
}

double ToSeconds(const Stamp& s) { return s.sec + s.nanosec * 1e-9; }

// As services/dds/messages.cpp FromMsgPose: TUM files of both runs are then bit-comparable.
Eigen::Isometry3d ToIsometry(double px, double py, double pz, double qx, double qy, double qz,
                             double qw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(px, py, pz);
  return T;
}

template <typename T>
void Store(std::uint8_t* p, T value) {
  std::memcpy(p, &value, sizeof(T));
}

// --- the participant, pinned to loopback ------------------------------------------------------

// Fast DDS 2.9 switches a participant to discovery-server client mode when these are set; the
// client must discover exactly as configured below, whatever the caller's environment holds.
void ClearDiscoveryEnvironment() {
  for (const char* name : {"ROS_DISCOVERY_SERVER", "ROS_SUPER_CLIENT"}) unsetenv(name);
}

Locator_t LoopbackLocator() {
  Locator_t locator;  // UDPv4, port 0: Fast DDS fills in the well-known RTPS port
  IPLocator::setIPv4(locator, 127, 0, 0, 1);
  return locator;
}

// UDPv4 on 127.0.0.1 only, no shared memory, no multicast; SPDP goes unicast to 127.0.0.1 on the
// well-known ports of participant indices 0..31, which is where Cyclone DDS with
// deploy/cyclonedds-loopback.xml (ParticipantIndex auto, MaxAutoParticipantIndex 32) listens,
// and it sends its own SPDP to the same range, so the two meet without multicast.
fdds::DomainParticipantQos LoopbackParticipantQos() {
  fdds::DomainParticipantQos qos;
  qos.name("dammloam-interop-fastdds");
  qos.transport().use_builtin_transports = false;  // no SHM, no default UDP on every interface
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList = {"127.0.0.1"};
  udp->maxInitialPeersRange = 32;
  udp->sendBufferSize = 1u << 20;
  udp->receiveBufferSize = 1u << 20;
  qos.transport().user_transports.push_back(udp);
  auto& builtin = qos.wire_protocol().builtin;
  builtin.initialPeersList.clear();
  builtin.initialPeersList.push_back(LoopbackLocator());
  // Explicit unicast locators (port 0 = well-known port of this participant id) and no
  // multicast locators: Fast DDS would otherwise announce 239.255.0.1 as well.
  builtin.metatrafficUnicastLocatorList.clear();
  builtin.metatrafficUnicastLocatorList.push_back(LoopbackLocator());
  builtin.metatrafficMulticastLocatorList.clear();
  qos.wire_protocol().default_unicast_locator_list.clear();
  qos.wire_protocol().default_unicast_locator_list.push_back(LoopbackLocator());
  qos.wire_protocol().default_multicast_locator_list.clear();
  return qos;
}

// Owns a participant and every entity created in it.
class Participant {
 public:
  explicit Participant(std::uint32_t domain) {
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    participant_ = factory->create_participant(static_cast<fdds::DomainId_t>(domain),
                                               LoopbackParticipantQos());
    if (participant_ == nullptr) throw std::runtime_error("cannot create the Fast DDS participant");
    publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (publisher_ == nullptr || subscriber_ == nullptr) {
      throw std::runtime_error("cannot create the Fast DDS publisher/subscriber");
    }
  }
  ~Participant() {
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  fdds::Topic* MakeTopic(fdds::TypeSupport type, const std::string& name) {
    if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("cannot register type " + type.get_type_name());
    }
    fdds::Topic* topic =
        participant_->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    if (topic == nullptr) throw std::runtime_error("cannot create topic " + name);
    return topic;
  }
  fdds::DataWriter* MakeWriter(fdds::Topic* topic, const fdds::DataWriterQos& qos) {
    fdds::DataWriter* writer = publisher_->create_datawriter(topic, qos);
    if (writer == nullptr) throw std::runtime_error("cannot create writer on " + topic->get_name());
    return writer;
  }
  fdds::DataReader* MakeReader(fdds::Topic* topic, const fdds::DataReaderQos& qos) {
    fdds::DataReader* reader = subscriber_->create_datareader(topic, qos);
    if (reader == nullptr) throw std::runtime_error("cannot create reader on " + topic->get_name());
    return reader;
  }

 private:
  fdds::DomainParticipant* participant_ = nullptr;
  fdds::Publisher* publisher_ = nullptr;
  fdds::Subscriber* subscriber_ = nullptr;
};

fdds::DataWriterQos WriterQos(bool reliable, int depth, bool transient_local) {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind =
      reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
  qos.durability().kind =
      transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = depth;
  // Clouds are larger than one datagram: fragments go out from Fast DDS's own thread.
  qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  qos.data_sharing().off();
  // XCDR1 (plain CDR), as Cyclone DDS 0.10 and ROS 2 Humble/Jazzy use for final types.
  qos.representation().m_value = {fdds::XCDR_DATA_REPRESENTATION};
  return qos;
}

fdds::DataReaderQos ReaderQos(bool reliable, int depth, bool transient_local) {
  fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
  qos.reliability().kind =
      reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
  qos.durability().kind =
      transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = depth;
  qos.data_sharing().off();
  qos.type_consistency().representation.m_value = {fdds::XCDR_DATA_REPRESENTATION};
  return qos;
}

bool WaitForMatch(fdds::DataWriter* writer, fdds::DataReader* reader, double seconds) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(seconds));
  while (Clock::now() < deadline) {
    fdds::PublicationMatchedStatus pub{};
    fdds::SubscriptionMatchedStatus sub{};
    writer->get_publication_matched_status(pub);
    reader->get_subscription_matched_status(sub);
    if (pub.current_count > 0 && sub.current_count > 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// --- the two wire layouts ----------------------------------------------------------------------

// Fields x y z intensity t(float32 s) ring(uint16), point_step 24: as dds::ScanToCloud.
dammloam::msg::PointCloud NativeCloud(const dammloam::Scan& scan, const std::string& frame_id,
                                      std::uint64_t seq) {
  namespace m = dammloam::msg;
  m::PointCloud cloud;
  const Stamp stamp = ToStamp(scan.t_start);
  cloud.header().stamp().sec(stamp.sec);
  cloud.header().stamp().nanosec(stamp.nanosec);
  cloud.header().frame_id(frame_id);
  cloud.header().seq(seq);
  cloud.height(1);
  cloud.width(static_cast<std::uint32_t>(scan.size()));
  auto field = [](const char* name, std::uint32_t offset, std::uint8_t datatype) {
    m::PointField f;
    f.name(name);
    f.offset(offset);
    f.datatype(datatype);
    f.count(1);
    return f;
  };
  cloud.fields({field("x", 0, m::DATATYPE_FLOAT32), field("y", 4, m::DATATYPE_FLOAT32),
                field("z", 8, m::DATATYPE_FLOAT32), field("intensity", 12, m::DATATYPE_FLOAT32),
                field("t", 16, m::DATATYPE_FLOAT32), field("ring", 20, m::DATATYPE_UINT16)});
  cloud.is_bigendian(false);
  cloud.point_step(24);
  cloud.row_step(cloud.point_step() * cloud.width());
  std::vector<std::uint8_t> data(std::size_t{cloud.row_step()}, 0);
  const bool has_intensity = scan.intensities.size() == scan.size();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    std::uint8_t* p = data.data() + i * cloud.point_step();
    Store(p + 0, static_cast<float>(scan.points[i].x()));
    Store(p + 4, static_cast<float>(scan.points[i].y()));
    Store(p + 8, static_cast<float>(scan.points[i].z()));
    Store(p + 12, has_intensity ? scan.intensities[i] : 0.0f);
    Store(p + 16, scan.has_times() ? scan.times[i] : 0.0f);
    Store(p + 20, static_cast<std::uint16_t>(scan.has_rings() ? scan.rings[i] : 0));
  }
  cloud.data(std::move(data));
  cloud.is_dense(true);
  return cloud;
}

// ouster-ros point layout (PointOS): x@0 y@4 z@8 intensity@16 float32, t@20 uint32 ns since
// header.stamp, reflectivity@24 ring@26 ambient@28 uint16, range@32 uint32 mm; point_step 48.
// `inexact_times` counts points whose float32 time does not survive the trip through integer
// nanoseconds (the daemon reads t as ns * 1e-9 and stores float32).
sensor_msgs::msg::dds_::PointCloud2_ OusterCloud(const dammloam::Scan& scan,
                                                 const std::string& frame_id,
                                                 std::size_t* inexact_times) {
  namespace m = sensor_msgs::msg::dds_;
  namespace c = sensor_msgs::msg::dds_::PointField_Constants;
  m::PointCloud2_ cloud;
  const Stamp stamp = ToStamp(scan.t_start);
  cloud.header().stamp().sec(stamp.sec);
  cloud.header().stamp().nanosec(stamp.nanosec);
  cloud.header().frame_id(frame_id);
  cloud.height(1);
  cloud.width(static_cast<std::uint32_t>(scan.size()));
  auto field = [](const char* name, std::uint32_t offset, std::uint8_t datatype) {
    m::PointField_ f;
    f.name(name);
    f.offset(offset);
    f.datatype(datatype);
    f.count(1);
    return f;
  };
  cloud.fields({field("x", 0, c::DATATYPE_FLOAT32), field("y", 4, c::DATATYPE_FLOAT32),
                field("z", 8, c::DATATYPE_FLOAT32), field("intensity", 16, c::DATATYPE_FLOAT32),
                field("t", 20, c::DATATYPE_UINT32), field("reflectivity", 24, c::DATATYPE_UINT16),
                field("ring", 26, c::DATATYPE_UINT16), field("ambient", 28, c::DATATYPE_UINT16),
                field("range", 32, c::DATATYPE_UINT32)});
  cloud.is_bigendian(false);
  cloud.point_step(48);
  cloud.row_step(cloud.point_step() * cloud.width());
  std::vector<std::uint8_t> data(std::size_t{cloud.row_step()}, 0);
  const bool has_intensity = scan.intensities.size() == scan.size();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    std::uint8_t* p = data.data() + i * cloud.point_step();
    const float intensity = has_intensity ? scan.intensities[i] : 0.0f;
    const float t = scan.has_times() ? scan.times[i] : 0.0f;
    const auto t_ns = static_cast<std::uint32_t>(std::llround(static_cast<double>(t) * 1e9));
    if (static_cast<float>(t_ns * 1e-9) != t) ++*inexact_times;
    Store(p + 0, static_cast<float>(scan.points[i].x()));
    Store(p + 4, static_cast<float>(scan.points[i].y()));
    Store(p + 8, static_cast<float>(scan.points[i].z()));
    Store(p + 16, intensity);
    Store(p + 20, t_ns);
    Store(p + 24, static_cast<std::uint16_t>(std::lround(std::min(intensity, 65535.0f))));
    Store(p + 26, static_cast<std::uint16_t>(scan.has_rings() ? scan.rings[i] : 0));
    Store(p + 28, std::uint16_t{0});
    Store(p + 32, static_cast<std::uint32_t>(std::llround(scan.points[i].norm() * 1000.0)));
  }
  cloud.data(std::move(data));
  cloud.is_dense(true);
  return cloud;
}

struct ReceivedPose {
  Stamp stamp;
  Eigen::Isometry3d T;
};

std::optional<ReceivedPose> TakePose(fdds::DataReader* reader, bool ros2) {
  fdds::SampleInfo info;
  if (ros2) {
    nav_msgs::msg::dds_::Odometry_ odom;
    if (reader->take_next_sample(&odom, &info) != ReturnCode_t::RETCODE_OK) return std::nullopt;
    if (!info.valid_data) return ReceivedPose{};
    const auto& p = odom.pose().pose();
    return ReceivedPose{{odom.header().stamp().sec(), odom.header().stamp().nanosec()},
                        ToIsometry(p.position().x(), p.position().y(), p.position().z(),
                                   p.orientation().x(), p.orientation().y(), p.orientation().z(),
                                   p.orientation().w())};
  }
  dammloam::msg::Odometry odom;
  if (reader->take_next_sample(&odom, &info) != ReturnCode_t::RETCODE_OK) return std::nullopt;
  if (!info.valid_data) return ReceivedPose{};
  const auto& p = odom.pose();
  return ReceivedPose{{odom.header().stamp().sec(), odom.header().stamp().nanosec()},
                      ToIsometry(p.position().x(), p.position().y(), p.position().z(),
                                 p.orientation().x(), p.orientation().y(), p.orientation().z(),
                                 p.orientation().w())};
}

int Run(const Options& o) {
  const bool ros2 = o.mode == "ros2";
  const std::string points_topic =
      !o.points_topic.empty() ? o.points_topic : (ros2 ? "rt/points" : "dammloam_points");
  const std::string odometry_topic = !o.odometry_topic.empty()
                                         ? o.odometry_topic
                                         : (ros2 ? "rt/dammloam/odometry" : "dammloam_odometry");
  const auto sequence = dammloam::io::SequenceReader::Open(o.sequence);

  ClearDiscoveryEnvironment();
  Participant participant(o.domain);
  fdds::DataWriter* writer = nullptr;
  fdds::DataReader* reader = nullptr;
  if (ros2) {
    // ROS 2 sensor data (rclcpp::SensorDataQoS): best effort, keep-last 5, volatile; odometry:
    // rclcpp default, reliable keep-last 10 volatile.
    writer = participant.MakeWriter(
        participant.MakeTopic(fdds::TypeSupport(new sensor_msgs::msg::dds_::PointCloud2_PubSubType()),
                              points_topic),
        WriterQos(false, 5, false));
    reader = participant.MakeReader(
        participant.MakeTopic(fdds::TypeSupport(new nav_msgs::msg::dds_::Odometry_PubSubType()),
                              odometry_topic),
        ReaderQos(true, 10, false));
  } else {
    // services/dds/topics.hpp: PointsQos reliable keep-last 4 volatile, OdometryQos reliable
    // keep-last 100 transient-local.
    writer = participant.MakeWriter(
        participant.MakeTopic(fdds::TypeSupport(new dammloam::msg::PointCloudPubSubType()),
                              points_topic),
        WriterQos(true, 4, false));
    reader = participant.MakeReader(
        participant.MakeTopic(fdds::TypeSupport(new dammloam::msg::OdometryPubSubType()),
                              odometry_topic),
        ReaderQos(true, 100, true));
  }
  if (!WaitForMatch(writer, reader, o.wait_daemon)) {
    std::cerr << "dammloam-interop-fastdds: dammloamd not matched on '" << points_topic
              << "' and '" << odometry_topic << "' (domain " << o.domain << ") within "
              << o.wait_daemon << " s: is it running on loopback with the same domain"
              << (ros2 ? " and --ros2" : "") << "?\n";
    return 3;
  }
  std::cout << "matched dammloamd on '" << points_topic << "' / '" << odometry_topic
            << "' (domain " << o.domain << "); publishing " << sequence.size() << " scans ("
            << o.mode << ") in lock-step" << std::endl;

  std::vector<dammloam::io::StampedPose> poses;
  std::size_t inexact_times = 0, resends = 0, other_poses = 0;
  const auto t0 = Clock::now();
  for (std::size_t k = 0; k < sequence.size(); ++k) {
    const dammloam::Scan scan = sequence.ReadScan(k);
    const Stamp stamp = ToStamp(scan.t_start);
    std::optional<sensor_msgs::msg::dds_::PointCloud2_> ouster;
    std::optional<dammloam::msg::PointCloud> native;
    if (ros2) {
      ouster = OusterCloud(scan, o.frame_id, &inexact_times);
    } else {
      native = NativeCloud(scan, o.frame_id, k);
    }
    auto publish = [&] {
      const bool ok = ros2 ? writer->write(&*ouster) : writer->write(&*native);
      if (!ok) std::cerr << "dammloam-interop-fastdds: write of scan " << k << " failed\n";
    };
    publish();
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(o.pose_timeout));
    auto next_resend = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(o.resend_after));
    bool found = false;
    while (!found && Clock::now() < deadline) {
      reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(0, 50000000));
      while (auto pose = TakePose(reader, ros2)) {
        if (pose->stamp == stamp) {
          poses.push_back({ToSeconds(stamp), pose->T});
          found = true;
        } else if (!(pose->stamp == Stamp{})) {
          ++other_poses;
        }
      }
      // Discovery is asymmetric: our writer may match the daemon's reader before the daemon's
      // reader knows our writer, and Cyclone DDS starts a volatile reader at the writer's first
      // heartbeat, so a scan written in that window is never delivered, reliable or not (a
      // best-effort one may also just be lost). Publish it again; the daemon rejects a duplicate
      // stamp, so a resend never yields two poses.
      if (!found && Clock::now() >= next_resend) {
        ++resends;
        std::cout << "no pose for scan " << k << " after " << o.resend_after
                  << " s: publishing it again" << std::endl;
        publish();
        next_resend = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                         std::chrono::duration<double>(o.resend_after));
      }
    }
    if (!found) {
      std::cerr << "dammloam-interop-fastdds: no pose for scan " << k << " of " << sequence.size()
                << " (stamp " << stamp.sec << "." << stamp.nanosec << ") on '" << odometry_topic
                << "' within " << o.pose_timeout << " s; " << poses.size()
                << " poses received so far\n";
      if (!o.out.empty()) dammloam::io::WriteTum(o.out, poses);
      return 4;
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!o.out.empty()) dammloam::io::WriteTum(o.out, poses);
  std::cout << "received " << poses.size() << " of " << sequence.size() << " poses in " << seconds
            << " s (" << resends << " resends, " << other_poses << " other poses)" << std::endl;
  if (ros2) {
    std::cout << "time quantization: " << inexact_times
              << " point times not exactly representable in uint32 ns" << std::endl;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"dammloam-interop-fastdds: drive dammloamd from an eProsima Fast DDS participant"};
  app.add_option("SEQUENCE_DIR", o.sequence, "sequence directory")
      ->required()->check(CLI::ExistingDirectory);
  app.add_option("--mode", o.mode, "native (dammloam types) or ros2 (ROS 2 types, rt/ topics)")
      ->check(CLI::IsMember({"native", "ros2"}));
  app.add_option("--domain", o.domain, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--out", o.out, "TUM file for the received poses");
  app.add_option("--points-topic", o.points_topic, "DDS topic of the clouds");
  app.add_option("--odometry-topic", o.odometry_topic, "DDS topic of the poses");
  app.add_option("--frame-id", o.frame_id, "header.frame_id of the clouds");
  app.add_option("--wait-daemon", o.wait_daemon, "seconds to wait for dammloamd")
      ->check(CLI::PositiveNumber);
  app.add_option("--pose-timeout", o.pose_timeout, "seconds to wait for each pose")
      ->check(CLI::PositiveNumber);
  app.add_option("--resend-after", o.resend_after,
                 "seconds before a scan without pose is published again")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    return Run(o);
  } catch (const std::exception& e) {
    std::cerr << "dammloam-interop-fastdds: " << e.what() << "\n";
    return 2;
  }
}
