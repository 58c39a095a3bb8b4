// One recorded sensor_msgs/msg/PointCloud2 message: io::DecodePointCloud2 (CDR of either byte
// order) and CloudToScan with the limits of recorded input (stamps at the start or the end of
// the sweep, the driver layouts of core/cloud).
//
// Input: the message's CDR bytes, encapsulation header included. DecodePointCloud2 throws
// io::IoError for bytes that are not a PointCloud2; CloudToScan reports, never throws; a
// converted scan must be consistent.
#include <cmath>
#include <cstdint>

#include "io/bag/bag_scans.hpp"
#include "io/bag/pointcloud2_cdr.hpp"
#include "io/bag/ros2_output.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::fuzz;

void Run(Input& in) {
  const std::span<const std::uint8_t> bytes = in.Rest();
  try {
    const io::DecodedCloud cloud = io::DecodePointCloud2(bytes.data(), bytes.size(), 0, "fuzz");
    const CloudInput view = cloud.View();
    if (view.data_size > bytes.size()) Finding("DecodePointCloud2: data larger than the message");
    CloudLimits limits = io::RecordedCloudLimits();
    limits.max_bytes = 1u << 20;
    const CloudConversion c = CloudToScan(view, limits);
    if (!c.scan) {
      if (c.error.empty()) Finding("CloudToScan failed without an error text");
      return;
    }
    const Scan& s = *c.scan;
    if (s.empty()) Finding("CloudToScan succeeded with no points");
    if ((!s.times.empty() && s.times.size() != s.size()) ||
        (!s.rings.empty() && s.rings.size() != s.size())) {
      Finding("CloudToScan: per-point vectors of different lengths");
    }
    for (float t : s.times) {
      if (!(t >= 0.0f && t <= 2.0 * limits.max_point_time)) Finding("point time out of range");
    }
    if (!std::isfinite(s.t_start)) Finding("non-finite t_start");
  } catch (const io::IoError&) {
    // documented: not a PointCloud2
  }
}

// --- seeds: the layouts of the project's own output and of the drivers ---------------------

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>&) {
  Cloud2 cloud;
  cloud.stamp = {1700000000, 123456789};
  cloud.frame_id = "lidar";
  cloud.width = 4;
  cloud.fields = {{"x", 0, point_field::kFloat32, 1}, {"y", 4, point_field::kFloat32, 1},
                  {"z", 8, point_field::kFloat32, 1}, {"intensity", 12, point_field::kFloat32, 1},
                  {"t", 16, point_field::kUint32, 1}, {"ring", 20, point_field::kUint16, 1}};
  cloud.point_step = 24;
  cloud.row_step = 96;
  cloud.data.assign(96, 0);
  for (std::uint32_t i = 0; i < 4; ++i) {
    const float xyz[4] = {1.0f + i, 2.0f, 0.5f, 10.0f};
    const std::uint32_t t = 1000 * i;
    const std::uint16_t ring = static_cast<std::uint16_t>(i);
    std::memcpy(cloud.data.data() + 24 * i, xyz, 16);
    std::memcpy(cloud.data.data() + 24 * i + 16, &t, 4);
    std::memcpy(cloud.data.data() + 24 * i + 20, &ring, 2);
  }
  WriteSeed(dir, "ouster-like", io::PointCloud2Cdr(cloud));
  cloud.fields[4] = {"time", 16, point_field::kFloat32, 1};
  cloud.height = 2;
  cloud.width = 2;
  cloud.row_step = 48;
  WriteSeed(dir, "organised-float-time", io::PointCloud2Cdr(cloud));
  std::vector<Eigen::Vector3d> points = {{1, 2, 3}, {4, 5, 6}};
  WriteSeed(dir, "labelled", io::PointCloud2Cdr(LabelledRos2Cloud(points, {}, {PointClass{}, PointClass{}}, "lidar")));
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
