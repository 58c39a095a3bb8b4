// Ouster: metadata JSON (ParseMetadata) and lidar packet decoding (PacketDecoder), then the
// point cloud (CloudMaker), as dammloam-driver runs them.
//
// Input: <metadata JSON> NUL <flags> <packets...>
//   flags: bit 0 CloudConfig::second_return, bit 1 CloudConfig::signal_intensity
//   each packet: one byte c; c == 0xFF: u16 length + that many bytes (any size, to exercise the
//   size checks); otherwise exactly one packet of the layout's size.
// Bad metadata must throw DriverError; packets never throw.
#include <nlohmann/json.hpp>

#include <cstdint>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::drivers;
using namespace dammloam::fuzz;

void CheckScan(const Scan& scan) {
  const std::size_t n = scan.size();
  if (scan.times.size() != n || scan.rings.size() != n || scan.intensities.size() != n) {
    Finding("CloudMaker::ToScan returned per-point vectors of different lengths");
  }
}

void Run(Input& in) {
  const std::string_view json = in.UntilNul();
  ouster::Metadata meta;
  try {
    meta = ouster::ParseMetadata(json, "fuzz.json");
  } catch (const DriverError&) {
    return;  // documented: unusable metadata
  }
  (void)ouster::ToSensorModel(meta);
  const auto flags = in.Get<std::uint8_t>();
  const ouster::CloudMaker cloud(meta, {(flags & 1) != 0, (flags & 2) != 0});
  ouster::PacketDecoder decoder(meta);
  const std::size_t packet_size = decoder.layout().packet;
  while (!in.empty()) {
    const auto c = in.Get<std::uint8_t>();
    const std::size_t size = c == 0xFF ? in.Get<std::uint16_t>() : packet_size;
    const auto packet = in.Bytes(size);
    if (auto frame = decoder.Push(packet)) {
      if (!frame->complete || frame->rows != meta.pixels_per_column || frame->cols != meta.columns_per_frame) {
        Finding("PacketDecoder returned an incomplete or misshaped frame");
      }
      CheckScan(cloud.ToScan(*frame));
      (void)ouster::Destagger(frame->range, frame->rows, frame->cols, meta.pixel_shift_by_row);
    }
  }
  decoder.Flush();
}

// --- seeds --------------------------------------------------------------------------------

// A tiny sensor (4 beams, 32 columns, 8 columns per packet) so that a frame is 4 packets.
std::string SmallMetadata(const std::string& profile, bool nested) {
  nlohmann::json beams = {{"beam_altitude_angles", {15.0, 5.0, -5.0, -15.0}},
                          {"beam_azimuth_angles", {3.0, 1.0, -1.0, -3.0}},
                          {"lidar_origin_to_beam_origin_mm", 15.8}};
  nlohmann::json format = {{"pixels_per_column", 4},     {"columns_per_frame", 32},
                           {"columns_per_packet", 8},    {"column_window", {0, 31}},
                           {"pixel_shift_by_row", {3, 1, -1, -3}},
                           {"udp_profile_lidar", profile}};
  nlohmann::json lidar = {{"lidar_to_sensor_transform",
                           {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1}}};
  if (nested) {
    return nlohmann::json{{"beam_intrinsics", beams},
                          {"lidar_data_format", format},
                          {"lidar_intrinsics", lidar},
                          {"config_params", {{"lidar_mode", "32x10"}, {"udp_port_lidar", 7502}}},
                          {"sensor_info", {{"prod_line", "OS-1-32"}}}}
        .dump();
  }
  nlohmann::json flat = beams;
  flat["data_format"] = format;
  flat["lidar_mode"] = "32x10";
  flat["prod_line"] = "OS-0-32";
  flat.update(lidar);
  return flat.dump();
}

void PutLE(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

// One packet of `meta`'s layout: columns first_column.. of frame `frame_id`, valid, ranges set.
std::vector<std::uint8_t> SyntheticPacket(const ouster::Metadata& meta, std::uint32_t frame_id, int first_column) {
  const ouster::PacketLayout l = ouster::LayoutFor(meta);
  std::vector<std::uint8_t> p(l.packet, 0);
  const bool legacy = meta.profile == ouster::Profile::kLegacy;
  if (meta.profile == ouster::Profile::kFusaRng15Rfl8Nir8Dual) {
    PutLE(p, 4, frame_id, 4);
  } else if (!legacy) {
    PutLE(p, 0, 1, 2);
    PutLE(p, 2, frame_id, 2);
  }
  for (int c = 0; c < meta.columns_per_packet; ++c) {
    const std::size_t col = l.packet_header + static_cast<std::size_t>(c) * l.column;
    const int mid = first_column + c;
    PutLE(p, col, 1'000'000'000ull + static_cast<std::uint64_t>(mid) * 97'656, 8);
    PutLE(p, col + 8, static_cast<std::uint64_t>(mid), 2);
    if (legacy) {
      PutLE(p, col + 10, frame_id, 2);
      PutLE(p, col + 12, static_cast<std::uint64_t>(mid) * 88, 4);
      PutLE(p, col + l.column - 4, 0xFFFFFFFFu, 4);
    } else {
      PutLE(p, col + 10, 1, 2);
    }
    for (int h = 0; h < meta.pixels_per_column; ++h) {
      const std::size_t px = col + l.column_header + static_cast<std::size_t>(h) * l.pixel;
      PutLE(p, px, 4000 + 100u * static_cast<unsigned>(h), l.pixel >= 8 ? 3 : 2);
      p[px + l.pixel - 1] = static_cast<std::uint8_t>(h + 1);
    }
  }
  return p;
}

void AppendPacket(Bytes& b, std::span<const std::uint8_t> packet, std::size_t layout_size) {
  if (packet.size() == layout_size) {
    b.Put<std::uint8_t>(0);
  } else {
    b.Put<std::uint8_t>(0xFF).Put(static_cast<std::uint16_t>(std::min<std::size_t>(packet.size(), 0xFFFF)));
  }
  b.Append(packet.first(std::min<std::size_t>(packet.size(), 0xFFFF)));
}

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>& shared) {
  int n = 0;
  for (const char* profile : {"LEGACY", "RNG19_RFL8_SIG16_NIR16", "RNG19_RFL8_SIG16_NIR16_DUAL",
                              "RNG15_RFL8_NIR8", "FUSA_RNG15_RFL8_NIR8_DUAL"}) {
    for (bool nested : {false, true}) {
      const std::string json = SmallMetadata(profile, nested);
      const auto meta = ouster::ParseMetadata(json);
      Bytes b;
      b.Append(json).Put<std::uint8_t>(0).Put<std::uint8_t>(nested ? 3 : 0);
      // Two whole frames, then a partial one and a short packet.
      for (std::uint32_t frame = 7; frame < 10; ++frame) {
        for (int first = 0; first < (frame == 9 ? 16 : 32); first += 8) {
          AppendPacket(b, SyntheticPacket(meta, frame, first), ouster::LayoutFor(meta).packet);
        }
      }
      AppendPacket(b, std::vector<std::uint8_t>(40, 0xAB), 0);
      WriteSeed(dir, "synthetic-" + std::to_string(n++), b.data);
    }
  }
  if (!shared) return;
  // Real metadata, alone and with the first packets of its capture (frames of 1024 columns do
  // not fit in an input; the synthetic seeds complete frames).
  std::vector<fs::path> jsons;
  for (const char* sub : {"ouster_sdk_pcaps", "velodyne_ouster_pcaps_rust_lidar_utils"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(*shared / sub, ec)) {
      if (e.path().extension() == ".json" && e.path().stem().string().find("digest") == std::string::npos) {
        jsons.push_back(e.path());
      }
    }
  }
  for (const fs::path& json_file : jsons) {
    const std::string json = ReadText(json_file);
    ouster::Metadata meta;
    try {
      meta = ouster::ParseMetadata(json, json_file.string());
    } catch (const DriverError&) {
      continue;
    }
    Bytes alone;
    alone.Append(json);
    WriteSeed(dir, "real-" + json_file.stem().string(), alone.data);
    const std::string stem = json_file.stem().string();
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(json_file.parent_path(), ec)) {
      const std::string name = e.path().stem().string();
      if (e.path().extension() != ".pcap" || name.rfind(stem.substr(0, stem.find("_1024")), 0) != 0) continue;
      try {
        PcapReader reader(e.path(), {meta.udp_port_lidar});
        UdpDatagram d;
        Bytes b;
        b.Append(json).Put<std::uint8_t>(0).Put<std::uint8_t>(0);
        for (int k = 0; k < 2 && reader.Next(d); ++k) AppendPacket(b, d.payload, ouster::LayoutFor(meta).packet);
        WriteSeed(dir, "real-" + name + "-packets", b.data);
      } catch (const DriverError&) {
      }
    }
  }
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
