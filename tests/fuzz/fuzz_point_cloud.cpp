// Incoming point clouds: CloudToScan over native dammloam PointCloud samples and ROS 2
// sensor_msgs/PointCloud2 samples (the daemon's two inputs, with the daemon's limits), and
// CloudToLabelled (what dammloam-record reads from LabelledCloud samples).
//
// Input (read front to back, missing bytes are 0):
//   u8 flags: bit 0 ROS 2 sample (else native); bit 1 is_bigendian; bit 2 is_dense; bit 3 make
//     row_step and the payload size consistent (width x point_step, height x row_step, payload
//     cut or zero-padded, when that is at most 256 KiB); bit 4 ROS 2: ros2.deskew off (else
//     auto), native: per-point times required; bit 5 also CloudToLabelled (native only)
//   i32 stamp.sec, u32 stamp.nanosec, u32 height, width, point_step, row_step
//   u8 field count (mod 16), then per field: u8 name (index into kNames; beyond it: u8 length +
//     that many bytes), u32 offset, u8 datatype, u32 count
//   the rest: data
// CloudToScan reports every problem in CloudConversion (never throws); on success the scan must
// be consistent. CloudToLabelled returns nullopt with an error text.
#include <cmath>
#include <cstdint>

#include "services/dammloamd/daemon_config.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/ros2_messages.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::fuzz;

constexpr const char* kNames[] = {"x",        "y",          "z",        "intensity", "t",
                                  "time",     "time_stamp", "ring",     "channel",   "map_x",
                                  "map_y",    "map_z",      "normal_x", "normal_y",  "normal_z",
                                  "label",    "rgb",        "",         "X",         "reflectivity"};
constexpr std::size_t kNumNames = sizeof(kNames) / sizeof(kNames[0]);
constexpr std::uint64_t kMaxConsistentBytes = 256 * 1024;

void CheckConversion(const dds::CloudConversion& c, const dds::CloudMessage& msg, const dds::CloudLimits& limits) {
  if (!c.scan) {
    if (c.error.empty() || c.code.empty()) Finding("CloudToScan failed without an error text or code");
    return;
  }
  const Scan& s = *c.scan;
  const std::size_t n = s.size();
  if (n == 0) Finding("CloudToScan succeeded with no points");
  if (n + c.skipped_points != std::uint64_t{msg.height} * msg.width) {
    Finding("CloudToScan: points + skipped differs from height x width");
  }
  if ((!s.times.empty() && s.times.size() != n) || (!s.rings.empty() && s.rings.size() != n) ||
      (!s.intensities.empty() && s.intensities.size() != n)) {
    Finding("CloudToScan: per-point vectors of different lengths");
  }
  for (const auto& p : s.points) {
    if (!p.allFinite()) Finding("CloudToScan returned a non-finite point");
  }
  for (float t : s.times) {
    if (!(t >= 0.0f && t <= 2.0 * limits.max_point_time)) Finding("CloudToScan returned a point time out of range");
  }
  for (std::int16_t r : s.rings) {
    if (r < 0 || r >= limits.max_ring) Finding("CloudToScan returned a ring out of range");
  }
}

void Run(Input& in) {
  const auto flags = in.Get<std::uint8_t>();
  const bool ros2 = (flags & 1) != 0;
  dds::CloudMessage msg;
  msg.is_bigendian = (flags & 2) != 0;
  msg.is_dense = (flags & 4) != 0;
  msg.stamp.sec = in.Get<std::int32_t>();
  msg.stamp.nanosec = in.Get<std::uint32_t>();
  msg.height = in.Get<std::uint32_t>();
  msg.width = in.Get<std::uint32_t>();
  msg.point_step = in.Get<std::uint32_t>();
  msg.row_step = in.Get<std::uint32_t>();
  const int num_fields = in.Get<std::uint8_t>() % 16;
  for (int i = 0; i < num_fields; ++i) {
    dds::CloudField f;
    const auto name = in.Get<std::uint8_t>();
    if (name < kNumNames) {
      f.name = kNames[name];
    } else {
      const auto bytes = in.Bytes(in.Get<std::uint8_t>());
      f.name.assign(bytes.begin(), bytes.end());
      f.name = f.name.c_str();  // the C sample carries a NUL-terminated string
    }
    f.offset = in.Get<std::uint32_t>();
    f.datatype = in.Get<std::uint8_t>();
    f.count = in.Get<std::uint32_t>();
    msg.fields.push_back(f);
  }
  const auto rest = in.Rest();
  msg.data.assign(rest.begin(), rest.end());
  if ((flags & 8) != 0) {
    const std::uint64_t row = std::uint64_t{msg.width} * msg.point_step;
    const std::uint64_t total = row * msg.height;
    if (row <= 0xFFFFFFFFu && total <= kMaxConsistentBytes) {
      msg.row_step = static_cast<std::uint32_t>(row);
      msg.data.resize(total, 0);
    }
  }

  // The daemon's limits (InputLimits / Ros2InputLimits in daemon.cpp) from its default config.
  const daemon::DaemonConfig config;
  dds::CloudLimits limits = config.limits;
  limits.max_ring = config.sensor.rings;
  if (ros2) {
    limits.point_times = (flags & 16) != 0 ? dds::PointTimes::kIgnored : dds::PointTimes::kRequired;
    limits.stamp_may_end_scan = true;
    limits.missing_time_hint = "set dammloamd.ros2.deskew: off";
    const dds::Ros2CloudView view(msg);
    CheckConversion(dds::CloudToScan(dds::ViewOf(view.get()), limits), msg, limits);
  } else {
    if ((flags & 16) != 0) limits.point_times = dds::PointTimes::kRequired;
    const dds::CloudView view(msg);
    CheckConversion(dds::CloudToScan(view.get(), limits), msg, limits);
    if ((flags & 32) != 0) {
      std::string error;
      const auto labelled = dds::CloudToLabelled(view.get(), &error);
      if (!labelled && error.empty()) Finding("CloudToLabelled failed without an error text");
      if (labelled) {
        const std::size_t n = labelled->points_sensor.size();
        if (labelled->points_map.size() != n || labelled->normals.size() != n || labelled->labels.size() != n) {
          Finding("CloudToLabelled: per-point vectors of different lengths");
        }
      }
    }
  }
}

// --- seeds --------------------------------------------------------------------------------

std::uint8_t NameIndex(const std::string& name) {
  for (std::size_t i = 0; i < kNumNames; ++i) {
    if (name == kNames[i]) return static_cast<std::uint8_t>(i);
  }
  return 0xFF;
}

// Encodes a CloudMessage in this target's input layout.
std::vector<std::uint8_t> Encode(const dds::CloudMessage& m, std::uint8_t flags) {
  Bytes b;
  b.Put(flags).Put(m.stamp.sec).Put(m.stamp.nanosec).Put(m.height).Put(m.width).Put(m.point_step).Put(m.row_step);
  b.Put(static_cast<std::uint8_t>(m.fields.size()));
  for (const auto& f : m.fields) {
    const std::uint8_t index = NameIndex(f.name);
    b.Put(index);
    if (index == 0xFF) b.Put(static_cast<std::uint8_t>(f.name.size())).Append(f.name);
    b.Put(f.offset).Put(f.datatype).Put(f.count);
  }
  b.Append(m.data);
  return b.data;
}

Scan SmallScan(int n, bool negative_times) {
  Scan s;
  s.t_start = 1700000000.25;
  for (int i = 0; i < n; ++i) {
    const double a = 0.3 * i;
    s.points.emplace_back(5.0 * std::cos(a), 5.0 * std::sin(a), 0.1 * (i % 7) - 0.3);
    s.intensities.push_back(static_cast<float>(i));
    s.times.push_back(static_cast<float>(0.1 * i / n) - (negative_times ? 0.1f : 0.0f));
    s.rings.push_back(static_cast<std::int16_t>(i % 16));
  }
  return s;
}

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>&) {
  int k = 0;
  auto write = [&](const dds::CloudMessage& m, std::uint8_t flags) {
    WriteSeed(dir, "cloud-" + std::to_string(k++), Encode(m, flags));
  };
  // The project's own clouds: ScanToCloud (native and ROS 2), LabelledToCloud, LabelledToRos2Cloud.
  dds::CloudMessage cloud = dds::ScanToCloud(SmallScan(24, false), "lidar", 5);
  write(cloud, 4);
  write(cloud, 4 | 16);
  write(cloud, 1 | 4);
  write(cloud, 1 | 4 | 16);
  write(dds::ScanToCloud(SmallScan(24, true), "lidar", 6), 1 | 4);
  cloud.is_dense = false;
  write(cloud, 0);
  dds::LabelledPoints labelled;
  for (int i = 0; i < 16; ++i) {
    labelled.points_sensor.emplace_back(i, 1.0, 2.0);
    labelled.points_map.emplace_back(i + 10.0, 1.0, 2.0);
    labelled.normals.emplace_back(0.f, 0.f, 1.f);
    labelled.labels.push_back(static_cast<PointClass>(i % kNumPointClasses));
  }
  write(dds::LabelledToCloud(labelled, "map", 1), 4 | 32);
  write(dds::LabelledToRos2Cloud(labelled, "lidar"), 1 | 4 | 16);
  // Driver layouts CloudToScan documents: ouster-ros (t uint32 ns, ring uint16), velodyne
  // (time float32 s, ring), nebula (time_stamp uint32 ns, channel), float64 xyz; 2 rows.
  struct Layout {
    std::vector<dds::CloudField> fields;
    std::uint32_t point_step;
  };
  const Layout layouts[] = {
      {{{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"intensity", 16, 7, 1}, {"t", 20, 6, 1}, {"ring", 24, 4, 1}}, 32},
      {{{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"intensity", 12, 7, 1}, {"ring", 16, 4, 1}, {"time", 18, 7, 1}}, 22},
      {{{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}, {"intensity", 12, 2, 1}, {"return_type", 13, 2, 1},
        {"channel", 14, 4, 1}, {"time_stamp", 16, 6, 1}}, 20},
      {{{"x", 0, 8, 1}, {"y", 8, 8, 1}, {"z", 16, 8, 1}, {"time", 24, 8, 1}, {"ring", 32, 1, 1}}, 33},
  };
  for (const Layout& l : layouts) {
    dds::CloudMessage m;
    m.height = 2;
    m.width = 6;
    m.fields = l.fields;
    m.point_step = l.point_step;
    m.row_step = m.point_step * m.width + 4;  // padded rows
    m.data.assign(std::size_t{m.row_step} * m.height, 0);
    for (std::uint32_t i = 0; i < m.height * m.width; ++i) {
      std::uint8_t* p = m.data.data() + (i / m.width) * m.row_step + (i % m.width) * m.point_step;
      for (const auto& f : l.fields) {
        const double v = f.name == "t" || f.name == "time_stamp" ? 1e6 * i : f.name == "time" ? 1e-3 * i : 1.0 + i;
        switch (f.datatype) {
          case 7: { const float x = static_cast<float>(v); std::memcpy(p + f.offset, &x, 4); break; }
          case 8: std::memcpy(p + f.offset, &v, 8); break;
          case 6: { const auto x = static_cast<std::uint32_t>(v); std::memcpy(p + f.offset, &x, 4); break; }
          case 4: { const auto x = static_cast<std::uint16_t>(i % 16); std::memcpy(p + f.offset, &x, 2); break; }
          default: p[f.offset] = static_cast<std::uint8_t>(i % 16); break;
        }
      }
    }
    write(m, 4);
    write(m, 1 | 4);
  }
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
