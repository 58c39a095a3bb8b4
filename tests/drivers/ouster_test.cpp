#include <gtest/gtest.h>
#include <openssl/evp.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/text_file.hpp"

namespace dammloam::drivers::ouster {
namespace {

using test::DataDir;

std::filesystem::path OusterDir() { return DataDir() / "ouster_sdk_pcaps"; }

template <typename T>
std::string Md5(const std::vector<T>& v) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  EVP_Digest(v.data(), v.size() * sizeof(T), digest, &len, EVP_md5(), nullptr);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  for (unsigned int i = 0; i < len; ++i) {
    s += kHex[digest[i] >> 4];
    s += kHex[digest[i] & 15];
  }
  return s;
}

struct Decoded {
  std::vector<LidarFrame> frames;
  Diagnostics decoder;
  Diagnostics pcap;
};

Decoded DecodeCapture(const std::filesystem::path& pcap, const Metadata& meta) {
  PacketDecoder decoder(meta);
  PcapReader reader(pcap, PcapFilter{meta.udp_port_lidar});
  Decoded out;
  UdpDatagram d;
  while (reader.Next(d)) {
    if (auto f = decoder.Push(d.payload)) out.frames.push_back(std::move(*f));
  }
  decoder.Flush();
  out.decoder = decoder.diagnostics();
  out.pcap = reader.diagnostics();
  return out;
}

// ---------------------------------------------------------------- metadata

TEST(OusterMetadata, FlatLayout) {
  const auto file = OusterDir() / "OS-1-32-G_v2.1.1_1024x10.json";
  DAMMLOAM_REQUIRE_DATA(file);
  const Metadata m = LoadMetadata(file);
  EXPECT_EQ(m.prod_line, "OS-1-32-G");
  EXPECT_EQ(m.pixels_per_column, 32);
  EXPECT_EQ(m.columns_per_frame, 1024);
  EXPECT_EQ(m.profile, Profile::kLegacy);  // no udp_profile_lidar key
  EXPECT_DOUBLE_EQ(m.beam_to_lidar(0, 3), 15.806);
  EXPECT_DOUBLE_EQ(m.lidar_to_sensor(0, 0), -1.0);
  EXPECT_DOUBLE_EQ(m.lidar_to_sensor(2, 3), 36.18);
  EXPECT_EQ(m.pixel_shift_by_row.size(), 32u);
  EXPECT_EQ(m.pixel_shift_by_row[4], 8);
  const SensorModel model = ToSensorModel(m);
  EXPECT_EQ(model.rings, 32);
  EXPECT_DOUBLE_EQ(model.scan_period, 0.1);
  EXPECT_EQ(model.vertical_angles_deg.size(), 32u);
  EXPECT_GT(model.vertical_angles_deg.front(), model.vertical_angles_deg.back());  // ring 0 on top
}

TEST(OusterMetadata, NestedLayout) {
  const auto file = OusterDir() / "OS-1-128_767798045_1024x10_20230712_120049.json";
  DAMMLOAM_REQUIRE_DATA(file);
  const Metadata m = LoadMetadata(file);
  EXPECT_EQ(m.prod_line, "OS-1-128");
  EXPECT_EQ(m.pixels_per_column, 128);
  EXPECT_EQ(m.profile, Profile::kFusaRng15Rfl8Nir8Dual);
  EXPECT_DOUBLE_EQ(m.beam_to_lidar(0, 3), 16.721);
  EXPECT_DOUBLE_EQ(m.lidar_to_sensor(2, 3), 38.195);
  EXPECT_EQ(m.udp_port_lidar, 7502);
  EXPECT_EQ(m.pixel_shift_by_row[0], 12);
  EXPECT_EQ(LayoutFor(m).packet, 16640u);
}

TEST(OusterMetadata, ModeSetsRateAndReducedFileGetsDefaults) {
  const auto os2 = OusterDir() / "OS-2-32-U0_v2.0.0_1024x10.json";
  const auto reduced = OusterDir() / "OS-1-64_sensor_config_reduced.json";
  DAMMLOAM_REQUIRE_DATA(os2);
  DAMMLOAM_REQUIRE_DATA(reduced);
  EXPECT_DOUBLE_EQ(ToSensorModel(LoadMetadata(os2)).scan_period, 0.05);  // 1024x20
  const Metadata m = LoadMetadata(reduced);
  EXPECT_EQ(m.pixels_per_column, 64);
  EXPECT_EQ(m.columns_per_frame, 1024);
  EXPECT_EQ(m.profile, Profile::kLegacy);
  EXPECT_TRUE(m.lidar_to_sensor.isIdentity());
  EXPECT_EQ(LayoutFor(m).packet, 12608u);
}

TEST(OusterMetadata, ErrorsNameTheField) {
  auto message = [](const std::string& json) {
    try {
      ParseMetadata(json, "m.json");
    } catch (const DriverError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{").find("not valid JSON"), std::string::npos);
  EXPECT_NE(message("{}").find("beam_altitude_angles"), std::string::npos);
  EXPECT_NE(message(R"({"beam_altitude_angles":[1,2],"beam_azimuth_angles":[1]})").find("beam_azimuth_angles"),
            std::string::npos);
  EXPECT_NE(message(R"({"beam_altitude_angles":[1],"beam_azimuth_angles":[1],
      "data_format":{"udp_profile_lidar":"NOPE"}})").find("udp_profile_lidar"), std::string::npos);
  EXPECT_NE(message(R"({"beam_altitude_angles":[1],"beam_azimuth_angles":[1],"lidar_mode":"fast"})").find("lidar_mode"),
            std::string::npos);
}

// ---------------------------------------------------------------- digests

struct DigestCase {
  const char* name;
};

class OusterDigest : public ::testing::TestWithParam<DigestCase> {};

TEST_P(OusterDigest, FieldsMatchSdkDigests) {
  const std::string name = GetParam().name;
  const auto pcap = OusterDir() / (name + ".pcap");
  const auto digest_file = OusterDir() / (name + "_digest.json");
  DAMMLOAM_REQUIRE_DATA(pcap);
  DAMMLOAM_REQUIRE_DATA(digest_file);
  const Metadata meta = LoadMetadata(OusterDir() / (name + ".json"));
  const auto digest = nlohmann::json::parse(test::ReadText(digest_file))["scans"][0];

  const Decoded d = DecodeCapture(pcap, meta);
  ASSERT_EQ(d.frames.size(), 1u) << d.decoder.Summary();
  const LidarFrame& f = d.frames[0];
  EXPECT_EQ(std::to_string(f.frame_id), digest["FRAME_ID"].get<std::string>());
  EXPECT_EQ(Md5(f.range), digest["RANGE"]);
  EXPECT_EQ(Md5(f.timestamp), digest["TIMESTAMP"]);
  EXPECT_EQ(Md5(f.measurement_id), digest["MEASUREMENT_ID"]);
  EXPECT_EQ(Md5(f.status), digest["STATUS"]);
  EXPECT_EQ(Md5(f.reflectivity), digest["REFLECTIVITY"]);
  EXPECT_EQ(Md5(f.near_ir), digest["NEAR_IR"]);
  // Fields a profile lacks are all zero in the SDK too, so every listed digest is checked.
  for (const char* field : {"SIGNAL", "RANGE2", "REFLECTIVITY2", "SIGNAL2", "ENCODER_COUNT"}) {
    if (!digest.contains(field)) continue;
    std::string md5;
    if (std::string(field) == "SIGNAL") md5 = Md5(f.signal);
    if (std::string(field) == "RANGE2") md5 = Md5(f.range2);
    if (std::string(field) == "REFLECTIVITY2") md5 = Md5(f.reflectivity2);
    if (std::string(field) == "SIGNAL2") md5 = Md5(f.signal2);
    if (std::string(field) == "ENCODER_COUNT") {  // the scan stores it widened to 64 bits
      md5 = Md5(std::vector<std::uint64_t>(f.encoder_count.begin(), f.encoder_count.end()));
    }
    EXPECT_EQ(md5, digest[field]) << field;
  }
  // The packet-level digest hashes the encoder counts as 32-bit values.
  const auto packet_hash = nlohmann::json::parse(test::ReadText(digest_file))["packet_hash"];
  EXPECT_EQ(Md5(f.encoder_count), packet_hash["ENCODER_COUNT"]);
  EXPECT_EQ(d.decoder.Get("partial_frames"), 0u);
  EXPECT_EQ(d.decoder.Get("invalid_columns"), 0u);
}

INSTANTIATE_TEST_SUITE_P(Captures, OusterDigest,
                         ::testing::Values(DigestCase{"OS-0-128-U1_v2.3.0_1024x10"},
                                           DigestCase{"OS-0-32-U1_v2.2.0_1024x10"},
                                           DigestCase{"OS-1-32-G_v2.1.1_1024x10"},
                                           DigestCase{"OS-2-32-U0_v2.0.0_1024x10"}),
                         [](const auto& info) {
                           std::string n = info.param.name;
                           for (char& c : n) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });


// ---------------------------------------------------------------- frames and clouds

TEST(OusterFrames, ThreeFrameSequenceDecodesToClouds) {
  const auto pcap = OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const Metadata meta = LoadMetadata(OusterDir() / "OS-1-128_v2.3.0_1024x10.json");
  const Decoded d = DecodeCapture(pcap, meta);
  ASSERT_EQ(d.frames.size(), 3u) << d.decoder.Summary();
  EXPECT_EQ(d.pcap.Get("other_ports"), 30u);  // IMU packets on 7503 filtered out
  const CloudMaker maker(meta);
  double previous_start = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(d.frames[k].frame_id, 1795u + k);
    const Scan scan = maker.ToScan(d.frames[k]);
    std::size_t valid = 0;
    for (auto r : d.frames[k].range) valid += r != 0;
    EXPECT_EQ(scan.size(), valid);
    EXPECT_GT(scan.size(), 100000u);  // README: ~107.5k of 131,072
    ASSERT_TRUE(scan.has_times());
    ASSERT_TRUE(scan.has_rings());
    const auto [tmin, tmax] = std::minmax_element(scan.times.begin(), scan.times.end());
    EXPECT_GE(*tmin, 0.0f);
    EXPECT_LT(*tmax, 0.1f);
    EXPECT_GT(*tmax, 0.095f);  // a frame spans ~0.0999 s
    EXPECT_GE(*std::min_element(scan.rings.begin(), scan.rings.end()), 0);
    EXPECT_LE(*std::max_element(scan.rings.begin(), scan.rings.end()), 127);
    if (k > 0) {
      EXPECT_NEAR(scan.t_start - previous_start, 0.1, 0.002);
    }
    previous_start = scan.t_start;
    // Firing order: times never decrease along the point list.
    EXPECT_TRUE(std::is_sorted(scan.times.begin(), scan.times.end()));
  }
}

// Destaggering must line up the beams: after it, the far points of one image column all look
// in (nearly) the same horizontal direction, while in the raw staggered image they spread by
// the beams' azimuth offsets (several degrees).
TEST(OusterFrames, DestaggerAlignsBeamAzimuths) {
  const auto pcap = OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const Metadata meta = LoadMetadata(OusterDir() / "OS-1-128_v2.3.0_1024x10.json");
  const Decoded d = DecodeCapture(pcap, meta);
  ASSERT_FALSE(d.frames.empty());
  const LidarFrame& f = d.frames[0];
  const CloudMaker maker(meta);
  const int H = f.rows, W = f.cols;
  // Azimuth (deg) of each pixel's point, staggered layout; NaN where there is no return.
  std::vector<double> az(f.range.size(), std::nan(""));
  for (int r = 0; r < H; ++r) {
    for (int c = 0; c < W; ++c) {
      const std::size_t i = static_cast<std::size_t>(r * W + c);
      if (f.range[i] < 5000) continue;
      const Eigen::Vector3d p = maker.Origin(r, c) + f.range[i] * 1e-3 * maker.Direction(r, c);
      az[i] = std::atan2(p.y(), p.x()) * 180.0 / M_PI;
    }
  }
  auto median_column_spread = [&](const std::vector<double>& img) {
    std::vector<double> spreads;
    for (int c = 0; c < W; ++c) {
      std::vector<double> v;
      for (int r = 0; r < H; ++r) {
        const double a = img[static_cast<std::size_t>(r * W + c)];
        if (!std::isnan(a)) v.push_back(a);
      }
      if (v.size() < 64) continue;
      const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
      if (*hi - *lo < 180.0) spreads.push_back(*hi - *lo);  // skip the +-180 seam
    }
    std::nth_element(spreads.begin(), spreads.begin() + static_cast<long>(spreads.size() / 2), spreads.end());
    return spreads[spreads.size() / 2];
  };
  const double staggered = median_column_spread(az);
  const double destaggered = median_column_spread(Destagger(az, H, W, meta.pixel_shift_by_row));
  EXPECT_GT(staggered, 5.0);
  EXPECT_LT(destaggered, 1.0);  // one column is 0.35 deg
}

TEST(OusterFrames, PartialFramesAreCountedNotEmitted) {
  const auto fusa = OusterDir() / "OS-1-128_767798045_1024x10_20230712_120049.pcap";
  DAMMLOAM_REQUIRE_DATA(fusa);
  const Decoded d = DecodeCapture(fusa, LoadMetadata(OusterDir() / "OS-1-128_767798045_1024x10_20230712_120049.json"));
  EXPECT_TRUE(d.frames.empty());
  EXPECT_EQ(d.decoder.Get("partial_frames"), 1u);
  EXPECT_EQ(d.decoder.Get("packets"), 8u);
  ASSERT_FALSE(d.decoder.messages().empty());
  EXPECT_NE(d.decoder.messages()[0].find("128 of 1024"), std::string::npos) << d.decoder.messages()[0];
}

TEST(OusterFrames, LegacyCaptureWithPartialFramesAtBothEnds) {
  const auto dir = DataDir() / "velodyne_ouster_pcaps_rust_lidar_utils";
  DAMMLOAM_REQUIRE_DATA(dir / "ouster_os1_64_example.pcap");
  const Metadata meta = LoadMetadata(dir / "ouster_os1_64_example.json");
  const Decoded d = DecodeCapture(dir / "ouster_os1_64_example.pcap", meta);
  ASSERT_EQ(d.frames.size(), 1u) << d.decoder.Summary();
  EXPECT_EQ(d.frames[0].frame_id, 12073u);
  EXPECT_EQ(d.decoder.Get("partial_frames"), 2u);  // 12072 (tail) and 12074 (head)
  EXPECT_EQ(CloudMaker(meta).ToScan(d.frames[0]).size(), 58797u);
}

TEST(OusterFrames, ReducedConfigCaptureDecodes) {
  const auto pcap = OusterDir() / "OS-1-64_1024x10_fw20.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const Metadata meta = LoadMetadata(OusterDir() / "OS-1-64_sensor_config_reduced.json");
  const Decoded d = DecodeCapture(pcap, meta);
  ASSERT_EQ(d.frames.size(), 1u) << d.decoder.Summary();
  EXPECT_EQ(d.frames[0].frame_id, 189u);
  EXPECT_EQ(CloudMaker(meta).ToScan(d.frames[0]).size(), 16749u);
}

// Damaged input: truncated packets, foreign payloads and IMU packets on the lidar port make
// the frames they hit incomplete; those are dropped with counters, the intact ones survive.
TEST(OusterFrames, DamagedPacketsNeverYieldCorruptFrames) {
  const auto pcap = OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const Metadata meta = LoadMetadata(OusterDir() / "OS-1-128_v2.3.0_1024x10.json");
  PacketDecoder decoder(meta);
  PcapReader reader(pcap);  // no port filter: IMU packets reach the decoder too
  UdpDatagram d;
  std::vector<LidarFrame> frames;
  int lidar_index = 0;
  while (reader.Next(d)) {
    if (d.dst_port == meta.udp_port_lidar) {
      ++lidar_index;
      if (lidar_index == 70) d.payload.resize(d.payload.size() / 2);  // truncated, in frame 2
      if (lidar_index == 71) std::fill(d.payload.begin(), d.payload.end(), std::uint8_t{0xAB});  // foreign
    }
    if (auto f = decoder.Push(d.payload)) frames.push_back(std::move(*f));
  }
  decoder.Flush();
  const auto& diag = decoder.diagnostics();
  EXPECT_EQ(diag.Get("short_packets"), 31u) << diag.Summary();  // 30 IMU + 1 truncated
  EXPECT_GE(diag.Get("partial_frames") + diag.Get("bad_measurement_ids"), 1u) << diag.Summary();
  ASSERT_EQ(frames.size(), 2u) << diag.Summary();
  EXPECT_EQ(frames[0].frame_id, 1795u);
  EXPECT_EQ(frames[1].frame_id, 1797u);
  for (const auto& f : frames) {
    EXPECT_TRUE(f.complete);
    EXPECT_EQ(std::count(f.column_received.begin(), f.column_received.end(), 1), 1024);
  }
}

TEST(OusterFrames, DualProfileSecondReturnAddsPoints) {
  const std::string name = "OS-0-32-U1_v2.2.0_1024x10";
  DAMMLOAM_REQUIRE_DATA(OusterDir() / (name + ".pcap"));
  const Metadata meta = LoadMetadata(OusterDir() / (name + ".json"));
  const Decoded d = DecodeCapture(OusterDir() / (name + ".pcap"), meta);
  ASSERT_EQ(d.frames.size(), 1u);
  const Scan first = CloudMaker(meta).ToScan(d.frames[0]);
  const Scan both = CloudMaker(meta, CloudConfig{.second_return = true}).ToScan(d.frames[0]);
  EXPECT_EQ(first.size(), 21631u);  // README: valid first-return pixels
  const auto second = static_cast<std::size_t>(std::count_if(d.frames[0].range2.begin(), d.frames[0].range2.end(),
                                                             [](auto r) { return r != 0; }));
  EXPECT_GT(second, 0u);
  EXPECT_EQ(both.size(), first.size() + second);
}

TEST(OusterFrames, StragglerPacketDoesNotBreakTheNextFrame) {
  const auto pcap = OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const Metadata meta = LoadMetadata(OusterDir() / "OS-1-128_v2.3.0_1024x10.json");
  std::vector<std::vector<std::uint8_t>> packets;
  PcapReader reader(pcap, PcapFilter{meta.udp_port_lidar});
  for (UdpDatagram d; reader.Next(d);) packets.push_back(d.payload);
  ASSERT_EQ(packets.size(), 192u);
  // Frame 1795's last packet arrives again after frame 1796 has started.
  packets.insert(packets.begin() + 65, packets[63]);
  PacketDecoder decoder(meta);
  std::size_t frames = 0;
  for (const auto& p : packets) frames += decoder.Push(p).has_value();
  EXPECT_EQ(frames, 3u) << decoder.diagnostics().Summary();
  EXPECT_EQ(decoder.diagnostics().Get("late_packets"), 1u);
}

}  // namespace
}  // namespace dammloam::drivers::ouster
