#include "tools/inputs/ouster_bag_source.hpp"

#include "drivers/ouster/metadata.hpp"
#include "io/bag/bag_reader.hpp"
#include "io/bag/byte_cursor.hpp"
#include "io/bag/cdr_reader.hpp"
#include "io/bag/ros1_bag.hpp"
#include "tools/inputs/packet_scans.hpp"

namespace dammloam::tools {
namespace {

namespace ouster = drivers::ouster;

bool IsPacketMsg(const io::BagTopic& t) {
  return t.type == "ouster_sensor_msgs/msg/PacketMsg" || t.type == "ouster_ros/msg/PacketMsg";
}

const io::BagTopic& PickPacketTopic(const io::BagReader& bag, const std::string& wanted,
                                    const std::filesystem::path& path) {
  const io::BagTopic* only = nullptr;
  const io::BagTopic* lidar = nullptr;
  std::size_t count = 0;
  for (const io::BagTopic& t : bag.topics()) {
    if (!IsPacketMsg(t)) continue;
    if (!wanted.empty() && t.name == wanted) return t;
    ++count;
    only = &t;
    if (t.name.size() >= 13 && t.name.compare(t.name.size() - 13, 13, "lidar_packets") == 0) lidar = &t;
  }
  if (wanted.empty() && lidar != nullptr) return *lidar;
  if (wanted.empty() && count == 1) return *only;
  throw io::IoError(path.string() + ": " +
                    (!wanted.empty() ? "no Ouster PacketMsg topic " + wanted
                     : count == 0    ? std::string("no Ouster PacketMsg topic")
                                     : std::string("several Ouster PacketMsg topics: pick one with --topic")) +
                    " (topics: " + io::TopicList(bag.topics()) + ")");
}

class OusterBagSource : public io::ScanSource {
 public:
  OusterBagSource(const std::filesystem::path& path, const std::string& topic,
                  const std::filesystem::path& metadata)
      : path_(path),
        bag_(io::OpenBag(path)),
        meta_(ouster::LoadMetadata(metadata)),
        scans_(meta_),
        model_(ouster::ToSensorModel(meta_)) {
    const io::BagTopic& t = PickPacketTopic(*bag_, topic, path);
    ros1_ = t.serialization_format == io::kRos1Serialization;
    describe_ = "Ouster " + (meta_.prod_line.empty() ? std::string("sensor") : meta_.prod_line) + " " +
                meta_.lidar_mode + " packets on " + t.name + ", metadata " + metadata.string() +
                "; stamps from the column timestamps";
    bag_->Select(t.name);
  }
  std::string kind() const override { return "ouster packets"; }
  std::string Describe() const override { return describe_; }
  const SensorModel& model() const override { return model_; }
  std::optional<std::size_t> size() const override { return std::nullopt; }
  std::optional<std::vector<io::StampedPose>> ReadGroundTruth() const override { return std::nullopt; }

  std::optional<Scan> Next() override {
    while (bag_->Next(message_)) {
      if (auto scan = scans_.Push(Payload())) return scan;
    }
    scans_.Flush();
    if (scans_.scans() == 0) {
      throw io::IoError(path_.string() + ": no complete Ouster frame with a return (packets of " +
                        std::to_string(ouster::LayoutFor(meta_).packet) + " bytes expected; decoder: " +
                        (scans_.diagnostics().counters().empty() ? std::string("nothing")
                                                                 : scans_.diagnostics().Summary()) +
                        ")");
    }
    return std::nullopt;
  }

 private:
  // PacketMsg: uint8[] buf, a length and the bytes of one UDP payload.
  std::span<const std::uint8_t> Payload() const {
    if (ros1_) {
      io::ByteCursor in(message_.data, message_.size, message_.data_offset, message_.where);
      const auto n = in.Read<std::uint32_t>("buf length");
      return {in.Bytes(n, "buf"), n};
    }
    io::CdrReader cdr(message_.data, message_.size, message_.data_offset, message_.where);
    const std::uint32_t n = cdr.SequenceLength("buf", 1);
    return {cdr.Bytes(n, "buf"), n};
  }

  std::filesystem::path path_;
  std::unique_ptr<io::BagReader> bag_;
  ouster::Metadata meta_;
  OusterScans scans_;
  SensorModel model_;
  std::string describe_;
  bool ros1_ = false;
  io::BagMessage message_;
};

}  // namespace

std::unique_ptr<io::ScanSource> OpenOusterBag(const std::filesystem::path& path, const std::string& topic,
                                              const std::filesystem::path& metadata) {
  return std::make_unique<OusterBagSource>(path, topic, metadata);
}

bool HasOusterPackets(const std::filesystem::path& path) {
  const std::unique_ptr<io::BagReader> bag = io::OpenBag(path);
  for (const io::BagTopic& t : bag->topics()) {
    if (IsPacketMsg(t)) return true;
  }
  return false;
}

}  // namespace dammloam::tools
