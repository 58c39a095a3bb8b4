// The MCAP reader (io::McapReader: magic, header, summary and its CRC, chunks with none/zstd/lz4
// and their CRCs, the data-section CRC, schemas, channels, messages) as dammloam-odometry reads
// an .mcap, with every message of a PointCloud2 channel decoded from CDR and converted.
//
// Input: the whole file, written to a scratch file since the reader takes a path. Records are
// limited to 4 MiB (a larger length is reported as corrupt). Only io::IoError may escape.
#include <cstdint>

#include "io/bag/bag_scans.hpp"
#include "io/bag/imu_messages.hpp"
#include "io/bag/mcap_reader.hpp"
#include "io/bag/mcap_writer.hpp"
#include "io/bag/pointcloud2_cdr.hpp"
#include "io/bag/ros2_output.hpp"
#include "io/bag/ros2_schemas.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::fuzz;

void Run(Input& in) {
  const std::span<const std::uint8_t> bytes = in.Rest();
  static const fs::path file = ScratchDir() / "input.mcap";
  WriteFile(file, bytes);
  try {
    io::McapReader reader(file, io::McapReadOptions{4u << 20});
    io::McapMessage m;
    for (int i = 0; i < 10000 && reader.Next(m); ++i) {
      if (m.size > bytes.size() * 1024 + (4u << 20)) Finding("McapReader returned an oversized message");
      const auto& channel = reader.channels().at(m.channel_id);
      const auto schema = reader.schemas().find(channel.schema_id);
      if (schema == reader.schemas().end() || schema->second.name != io::kPointCloud2Type) {
        try {  // any other message also as the sensor_msgs/Imu read along with the clouds
          io::DecodeImuCdr(m.data, m.size, m.data_offset, m.where);
        } catch (const io::IoError&) {
        }
        continue;
      }
      const io::DecodedCloud cloud = io::DecodePointCloud2(m.data, m.size, m.data_offset, m.where);
      const CloudConversion c = CloudToScan(cloud.View(), io::RecordedCloudLimits());
      if (c.scan && c.scan->empty()) Finding("CloudToScan succeeded with no points");
    }
  } catch (const io::IoError&) {
    // documented: every problem of the file
  }
}

// --- seeds: files from the project's own MCAP writer ---------------------------------------

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>&) {
  std::vector<Eigen::Vector3d> points;
  std::vector<PointClass> labels;
  for (int i = 0; i < 12; ++i) {
    points.emplace_back(1.0 + i, 0.5 * i, -0.2);
    labels.push_back(static_cast<PointClass>(i % kNumPointClasses));
  }
  for (const std::string compression : {"", "zstd"}) {
    const fs::path file = ScratchDir() / "seed.mcap";
    {
      io::McapWriter writer(file, {compression, 512, "ros2"});
      const auto cloud = writer.AddChannel(
          writer.AddSchema(io::kPointCloud2Type, "ros2msg", io::PointCloud2Schema()), "/points",
          "cdr", {{"offered_qos_profiles", ""}});
      const auto tf = writer.AddChannel(
          writer.AddSchema("tf2_msgs/msg/TFMessage", "ros2msg", io::TfMessageSchema()), "/tf",
          "cdr", {});
      for (int s = 0; s < 3; ++s) {
        Cloud2 msg = LabelledRos2Cloud(points, {}, labels, "lidar");
        msg.stamp = {100 + s, 5000};
        const std::uint64_t t = (100ull + s) * 1000000000ull;
        writer.Write(cloud, t, t, io::PointCloud2Cdr(msg));
        writer.Write(tf, t, t, io::TfCdr(msg.stamp, "odom", "lidar", Eigen::Isometry3d::Identity()));
      }
      writer.Close();
    }
    WriteSeed(dir, "written-" + (compression.empty() ? std::string("none") : compression), ReadFile(file));
  }
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
