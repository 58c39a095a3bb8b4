#include <gtest/gtest.h>
#include <openssl/evp.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "test_data.hpp"

namespace dammloam::drivers::ouster {
namespace {

using dammloam::drivers::testing::DataDir;

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
  const auto digest = nlohmann::json::parse(testing::ReadText(digest_file))["scans"][0];

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
  const auto packet_hash = nlohmann::json::parse(testing::ReadText(digest_file))["packet_hash"];
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

}  // namespace
}  // namespace dammloam::drivers::ouster
