#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/inertial/imu_sample.hpp"
#include "io/motion_csv.hpp"

// sensor_msgs/Imu recorded beside the clouds (ouster-ros publishes the sensor's IMU as
// /ouster/imu): read along with the scans so a bag carries what a sequence's imu.csv does.
namespace dammloam::io {

struct BagImu {
  std::string topic;
  std::string frame_id;            // of the first message: the IMU frame its extrinsic must name
  std::vector<ImuSample> samples;  // header stamps, seconds; strictly increasing
  StreamReadReport report;         // dropped messages by reason ("line" = message number, 1-based)
};

// `topic` empty: the bag's only sensor_msgs/msg/Imu topic, nullopt when it has none; several
// without a choice, or a named topic that is missing or of another type: IoError listing the
// topics. A message that does not decode: IoError naming the file, record and offset.
std::optional<BagImu> ReadBagImu(const std::filesystem::path& bag, const std::string& topic = {});

// One message. data: CDR with its encapsulation header, or ROS 1 serialisation.
ImuSample DecodeImuCdr(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                       const std::string& where, std::string* frame_id = nullptr);
ImuSample DecodeImuRos1(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                        const std::string& where, std::string* frame_id = nullptr);

}  // namespace dammloam::io
