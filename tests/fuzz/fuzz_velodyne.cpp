// Velodyne: calibration YAML (ParseCalibration) and data packet decoding (Decoder), as
// dammloam-driver runs them.
//
// Input: <flags> <calibration YAML> NUL <packets...>
//   flags: bits 0-1 model (vlp16, vlp32c, hdl32e, vls128); bit 2 use a nominal calibration built
//   in code (the YAML is still parsed, the decoder gets the nominal one: keeps the packet decoder
//   reachable when the YAML is broken); bit 3 dual_both_returns; bit 4 VLS-128 nebula azimuths;
//   bits 5-6 rpm (600, 300, 1200, 60); bit 7 scan phase 180 deg instead of 0.
//   each packet: one byte c; c == 0xFF: u16 length + that many bytes; otherwise 1206 bytes,
//   captured c * 0.1 ms after the previous one.
// A bad calibration must throw DriverError; packets never throw.
#include <cmath>
#include <cstdint>
#include <sstream>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::drivers;
using namespace dammloam::fuzz;

constexpr velodyne::Model kModels[] = {velodyne::Model::kVLP16, velodyne::Model::kVLP32C,
                                       velodyne::Model::kHDL32E, velodyne::Model::kVLS128};
constexpr double kRpm[] = {600.0, 300.0, 1200.0, 60.0};

// Evenly spread elevations, top beam first: what a datasheet-only calibration looks like.
velodyne::Calibration NominalCalibration(velodyne::Model model) {
  velodyne::Calibration cal;
  const int n = velodyne::LaserCount(model);
  cal.lasers.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    auto& l = cal.lasers[static_cast<std::size_t>(i)];
    l.id = i;
    l.ring = i;
    l.vert_correction = (15.0 - 30.0 * i / std::max(1, n - 1)) * M_PI / 180.0;
  }
  cal.source = "nominal";
  return cal;
}

void Run(Input& in) {
  const auto flags = in.Get<std::uint8_t>();
  const velodyne::Model model = kModels[flags & 3];
  const std::string yaml(in.UntilNul());
  velodyne::Calibration cal;
  bool parsed = false;
  try {
    cal = velodyne::ParseCalibration(yaml, "fuzz.yaml");
    parsed = true;
  } catch (const DriverError&) {
    // documented: unusable calibration
  }
  if (parsed) {
    for (std::size_t i = 0; i < cal.lasers.size(); ++i) {
      if (cal.lasers[i].id != static_cast<int>(i) || cal.lasers[i].ring < 0 ||
          cal.lasers[i].ring >= static_cast<int>(cal.lasers.size())) {
        Finding("ParseCalibration returned a laser with a bad id or ring");
      }
    }
  }
  if ((flags & 4) != 0) {
    cal = NominalCalibration(model);
  } else if (!parsed) {
    return;
  }
  velodyne::DecoderConfig config;
  config.model = model;
  config.dual_both_returns = (flags & 8) != 0;
  config.vls128_azimuth = (flags & 16) != 0 ? velodyne::Vls128Azimuth::kNebula : velodyne::Vls128Azimuth::kFiringTime;
  config.rpm = kRpm[(flags >> 5) & 3];
  config.scan_phase_deg = (flags & 128) != 0 ? 180.0 : 0.0;
  std::optional<velodyne::Decoder> decoder;
  try {
    decoder.emplace(config, cal);
  } catch (const DriverError&) {
    return;  // documented: the calibration does not fit the model
  }
  (void)decoder->sensor_model();
  double t = 1'700'000'000.0;
  while (!in.empty()) {
    const auto c = in.Get<std::uint8_t>();
    const std::size_t size = c == 0xFF ? in.Get<std::uint16_t>() : velodyne::kPacketSize;
    t += (c == 0xFF ? 0 : c) * 1e-4;
    if (auto scan = decoder->Push(in.Bytes(size), t)) {
      const std::size_t n = scan->size();
      if (n == 0 || scan->times.size() != n || scan->rings.size() != n || scan->intensities.size() != n) {
        Finding("Decoder returned an empty scan or per-point vectors of different lengths");
      }
      for (float time : scan->times) {
        if (!(time >= 0.0f && time < 60.0 / config.rpm)) Finding("Decoder returned a point time outside the scan period");
      }
    }
  }
  decoder->Flush();
}

// --- seeds --------------------------------------------------------------------------------

std::uint8_t ProductId(velodyne::Model m) {
  switch (m) {
    case velodyne::Model::kVLP16: return 0x22;
    case velodyne::Model::kVLP32C: return 0x28;
    case velodyne::Model::kHDL32E: return 0x21;
    case velodyne::Model::kVLS128: return 0xA1;
  }
  return 0;
}

std::string CalibrationYaml(int lasers) {
  std::ostringstream y;
  y << "num_lasers: " << lasers << "\ndistance_resolution: 0.002\nlasers:\n";
  for (int i = 0; i < lasers; ++i) {
    y << "  - {dist_correction: 0.0, laser_id: " << i << ", rot_correction: " << 0.001 * (i % 3)
      << ", vert_correction: " << (0.26 - 0.52 * i / std::max(1, lasers - 1))
      << ", vert_offset_correction: 0.0, horiz_offset_correction: 0.0}\n";
  }
  return y.str();
}

// `revolutions` turns in 8 packets each (a coarse but valid azimuth sweep), 0.1 s per turn.
void AppendSweep(Bytes& b, velodyne::Model model, bool dual, double revolutions) {
  const int packets = static_cast<int>(8 * revolutions);
  for (int k = 0; k < packets; ++k) {
    std::vector<std::uint8_t> p(velodyne::kPacketSize, 0);
    for (int blk = 0; blk < 12; ++blk) {
      const std::size_t at = static_cast<std::size_t>(blk) * 100;
      const bool vls = model == velodyne::Model::kVLS128;
      const std::uint16_t flag = vls ? static_cast<std::uint16_t>(0xEEFF - 0x1100 * (blk % 4)) : 0xEEFF;
      const int firing = vls ? blk / 4 : (dual ? blk / 2 : blk);
      const auto az = static_cast<std::uint16_t>((k * 12 + firing * (vls ? 4 : dual ? 2 : 1)) * 375 % 36000);
      std::memcpy(&p[at], &flag, 2);
      std::memcpy(&p[at + 2], &az, 2);
      for (int ch = 0; ch < 32; ++ch) {
        const auto raw = static_cast<std::uint16_t>(5000 + 10 * ch + (dual && blk % 2 ? 7 * (ch % 2) : 0));
        std::memcpy(&p[at + 4 + static_cast<std::size_t>(ch) * 3], &raw, 2);
        p[at + 6 + static_cast<std::size_t>(ch) * 3] = static_cast<std::uint8_t>(ch * 3);
      }
    }
    const auto usec = static_cast<std::uint32_t>(1'000'000 + k * 12'500);
    std::memcpy(&p[1200], &usec, 4);
    p[1204] = dual ? 0x39 : 0x37;
    p[1205] = ProductId(model);
    b.Put<std::uint8_t>(125).Append(p);  // 12.5 ms between packets
  }
}

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>& shared) {
  int n = 0;
  for (int m = 0; m < 4; ++m) {
    const velodyne::Model model = kModels[m];
    for (bool dual : {false, true}) {
      for (bool nominal : {true, false}) {
        Bytes b;
        b.Put(static_cast<std::uint8_t>(m | (nominal ? 4 : 0) | 8));
        if (!nominal) b.Append(CalibrationYaml(velodyne::LaserCount(model)));
        b.Put<std::uint8_t>(0);
        AppendSweep(b, model, dual, nominal ? 2.5 : 1.5);
        WriteSeed(dir, "synthetic-" + std::to_string(n++), b.data);
      }
    }
  }
  // The repo's calibration files on their own.
  for (const auto& [file, m] : {std::pair{"HDL32E.yaml", 2}, std::pair{"VLS128.yaml", 3}}) {
    Bytes b;
    b.Put(static_cast<std::uint8_t>(m)).Append(ReadText(SourceDir() / "drivers/calibration" / file));
    WriteSeed(dir, std::string("repo-") + file, b.data);
  }
  if (!shared) return;
  // Real captures with their calibration (or the nominal one), first packets only.
  struct Capture {
    const char* pcap;
    const char* calibration;  // relative to shared/, or to the repo when it starts with "repo:"
    int model;
  };
  const Capture captures[] = {
      {"velodyne_nebula_rosbag2/vlp16/vlp16_packets_from_rosbag2.pcap", "velodyne_nebula_rosbag2/calibration/VLP16.yaml", 0},
      {"velodyne_nebula_rosbag2/vlp32/vlp32_packets_from_rosbag2.pcap", "velodyne_nebula_rosbag2/calibration/VLP32.yaml", 1},
      {"velodyne_nebula_rosbag2/vls128/vls128_packets_from_rosbag2.pcap", "repo:VLS128.yaml", 3},
      {"velodyne_ouster_pcaps_rust_lidar_utils/hdl32e_example.pcap", "repo:HDL32E.yaml", 2},
      {"velodyne_ouster_pcaps_rust_lidar_utils/velodyne_vlp16.pcap", "velodyne_nebula_rosbag2/calibration/VLP16.yaml", 0},
  };
  for (const Capture& c : captures) {
    const std::string cal_name = c.calibration;
    const fs::path cal_file = cal_name.rfind("repo:", 0) == 0
                                  ? SourceDir() / "drivers/calibration" / cal_name.substr(5)
                                  : *shared / cal_name;
    if (!fs::exists(*shared / c.pcap) || !fs::exists(cal_file)) continue;
    for (bool nominal : {false, true}) {
      try {
        PcapReader reader(*shared / c.pcap);
        UdpDatagram d;
        Bytes b;
        b.Put(static_cast<std::uint8_t>(c.model | (nominal ? 4 : 0) | 8));
        if (!nominal) b.Append(ReadText(cal_file));
        b.Put<std::uint8_t>(0);
        double last = -1.0;
        for (int k = 0; k < (nominal ? 30 : 8) && reader.Next(d);) {
          if (d.payload.size() != velodyne::kPacketSize) continue;
          const double gap = last < 0 ? 0.0 : (d.capture_time - last) * 1e4;
          b.Put(static_cast<std::uint8_t>(std::clamp(gap, 0.0, 254.0))).Append(d.payload);
          last = d.capture_time;
          ++k;
        }
        WriteSeed(dir, std::string("real-") + fs::path(c.pcap).stem().string() + (nominal ? "-nominal" : ""), b.data);
      } catch (const DriverError&) {
      }
    }
  }
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
