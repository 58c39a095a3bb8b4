// The ROS 1 bag reader (io::Ros1Bag: bag header, index section or a scan pass, chunks stored /
// bz2 / lz4, connection and message-data records) as dammloam-odometry reads a .bag, with every
// message of a PointCloud2 topic decoded from the ROS 1 serialisation and converted, and every
// message of any other topic also decoded as a sensor_msgs/Imu (the IMU read along).
//
// Input: the whole file, written to a scratch file since the reader takes a path. Records and
// chunks are limited to 4 MiB (a larger length is reported as corrupt). Only io::IoError may
// escape.
#include <bzlib.h>
#include <lz4frame.h>

#include <cstdint>

#include "io/bag/bag_scans.hpp"
#include "io/bag/imu_messages.hpp"
#include "io/bag/pointcloud2_cdr.hpp"
#include "io/bag/ros1_bag.hpp"
#include "tests/bag/ros1_bag_bytes.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::fuzz;

void Run(Input& in) {
  const std::span<const std::uint8_t> bytes = in.Rest();
  static const fs::path file = ScratchDir() / "input.bag";
  WriteFile(file, bytes);
  try {
    io::Ros1Bag bag(file, io::BagReadOptions{4u << 20});
    const std::vector<io::BagTopic> topics = bag.topics();
    for (const io::BagTopic& topic : topics) {
      bag.Select(topic.name);
      io::BagMessage m;
      for (int i = 0; i < 1000 && bag.Next(m); ++i) {
        if (m.size > (4u << 20)) Finding("Ros1Bag returned a message larger than a chunk");
        if (topic.type != io::kPointCloud2Type) {
          try {
            io::DecodeImuRos1(m.data, m.size, m.data_offset, m.where);
          } catch (const io::IoError&) {
            // not an Imu: documented
          }
          continue;
        }
        const io::DecodedCloud cloud = io::DecodePointCloud2Ros1(m.data, m.size, m.data_offset, m.where);
        const CloudConversion c = CloudToScan(cloud.View(), io::RecordedCloudLimits());
        if (c.scan && c.scan->empty()) Finding("CloudToScan succeeded with no points");
      }
    }
  } catch (const io::IoError&) {
    // documented: every problem of the file
  }
}

// --- seeds: bags built from the format specification (tests/bag/ros1_bag_bytes.hpp) --------

std::string Bz2(const std::string& data) {
  std::string out(data.size() + data.size() / 100 + 700, '\0');
  unsigned int n = static_cast<unsigned int>(out.size());
  if (BZ2_bzBuffToBuffCompress(out.data(), &n, const_cast<char*>(data.data()),
                               static_cast<unsigned int>(data.size()), 9, 0, 0) != BZ_OK) {
    Finding("bz2 compression of a seed failed");
  }
  out.resize(n);
  return out;
}

std::string Lz4(const std::string& data) {
  std::string out(LZ4F_compressFrameBound(data.size(), nullptr), '\0');
  const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), data.data(), data.size(), nullptr);
  if (LZ4F_isError(n)) Finding("lz4 compression of a seed failed");
  out.resize(n);
  return out;
}

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>&) {
  std::vector<test::Ros1Message> messages;
  for (std::uint32_t s = 0; s < 3; ++s) {
    std::vector<float> xyzi;
    for (int i = 0; i < 8; ++i) xyzi.insert(xyzi.end(), {1.0f + static_cast<float>(i), 0.5f * static_cast<float>(s), -0.2f, 7.0f});
    messages.push_back({1, 100 + s, 0, std::string("\x02\x00\x00\x00hi", 6)});
    messages.push_back({2, 100 + s, 5000, test::Ros1PointCloud2(s, 100 + s, 5000, xyzi)});
  }
  const std::vector<test::Ros1Connection> connections = {{1, "/chatter", "std_msgs/String"},
                                                         {2, "/points", "sensor_msgs/PointCloud2"}};
  auto seed = [&](const std::string& name, const std::string& bag) {
    WriteSeed(dir, name, std::span(reinterpret_cast<const std::uint8_t*>(bag.data()), bag.size()));
  };
  seed("stored", test::BuildRos1Bag(connections, messages, "none", 2));
  seed("unindexed", test::BuildRos1Bag(connections, messages, "none", 4, false));
  seed("bz2", test::BuildRos1Bag(connections, messages, "bz2", 3, true, Bz2));
  seed("lz4", test::BuildRos1Bag(connections, messages, "lz4", 3, true, Lz4));
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
