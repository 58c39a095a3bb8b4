#include "tools/inputs/velodyne_bag_source.hpp"

#include <algorithm>
#include <deque>

#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "io/bag/bag_reader.hpp"
#include "io/bag/cdr_reader.hpp"
#include "io/bag/ros1_bag.hpp"
#include "tools/inputs/packet_scans.hpp"

namespace dammloam::tools {
namespace {

namespace velodyne = drivers::velodyne;
constexpr const char* kVelodyneScanType = "velodyne_msgs/msg/VelodyneScan";

std::string PickTopic(const io::BagReader& bag, const std::string& wanted,
                      const std::filesystem::path& path) {
  std::vector<std::string> found;
  for (const io::BagTopic& t : bag.topics()) {
    if (t.type != kVelodyneScanType) continue;
    if (wanted.empty() || t.name == wanted) found.push_back(t.name);
  }
  if (found.size() == 1) return found.front();
  throw io::IoError(path.string() + ": " +
                    (wanted.empty() ? std::string(found.empty() ? "no " : "several ") +
                                          kVelodyneScanType + " topic" +
                                          (found.empty() ? "" : "s: pick one with --topic")
                                    : "no " + std::string(kVelodyneScanType) + " topic " + wanted) +
                    " (topics: " + io::TopicList(bag.topics()) + ")");
}

class VelodyneBagSource : public io::ScanSource {
 public:
  VelodyneBagSource(const std::filesystem::path& path, const std::string& topic,
                    const std::string& model, const std::filesystem::path& calibration)
      : bag_(io::OpenBag(path)),
        decoder_(VelodyneDecoderConfig(model), velodyne::LoadCalibration(calibration)),
        model_(decoder_.sensor_model()) {
    const std::string name = PickTopic(*bag_, topic, path);
    for (const io::BagTopic& t : bag_->topics()) {
      if (t.name == name && t.serialization_format == io::kRos1Serialization) {
        throw io::IoError(path.string() + ": VelodyneScan packets of a ROS 1 bag are not read " +
                          "(rosbag2 or MCAP only); topic " + name);
      }
    }
    bag_->Select(name);
  }
  std::string kind() const override { return "velodyne packets"; }
  const SensorModel& model() const override { return model_; }
  std::optional<std::size_t> size() const override { return std::nullopt; }
  std::optional<Scan> Next() override {
    while (ready_.empty()) {
      if (!bag_->Next(message_)) {
        decoder_.Flush();
        return std::nullopt;
      }
      Decode();
    }
    Scan scan = std::move(ready_.front());
    ready_.pop_front();
    return scan;
  }
  std::optional<std::vector<io::StampedPose>> ReadGroundTruth() const override {
    return std::nullopt;
  }

 private:
  // velodyne_msgs/msg/VelodyneScan: std_msgs/Header, then VelodynePacket[] (a stamp and the
  // 1206 bytes of one UDP payload).
  void Decode() {
    io::CdrReader cdr(message_.data, message_.size, message_.data_offset, message_.where);
    cdr.I32("header.stamp.sec");
    cdr.U32("header.stamp.nanosec");
    cdr.String("header.frame_id");
    const std::uint32_t n = cdr.SequenceLength("packets", velodyne::kPacketSize);
    for (std::uint32_t i = 0; i < n; ++i) {
      const double sec = cdr.I32("packets[].stamp.sec");
      const double nanosec = cdr.U32("packets[].stamp.nanosec");
      const std::uint8_t* packet = cdr.Bytes(velodyne::kPacketSize, "packets[].data");
      if (auto scan = decoder_.Push({packet, velodyne::kPacketSize}, sec + nanosec * 1e-9)) {
        ready_.push_back(std::move(*scan));
      }
    }
  }

  std::unique_ptr<io::BagReader> bag_;
  velodyne::Decoder decoder_;
  SensorModel model_;
  io::BagMessage message_;
  std::deque<Scan> ready_;
};

}  // namespace

std::unique_ptr<io::ScanSource> OpenVelodyneBag(const std::filesystem::path& path,
                                                const std::string& topic, const std::string& model,
                                                const std::filesystem::path& calibration) {
  return std::make_unique<VelodyneBagSource>(path, topic, model, calibration);
}

}  // namespace dammloam::tools
