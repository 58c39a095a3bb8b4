#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "test_data.hpp"

namespace dammloam::drivers::velodyne {
namespace {

using dammloam::drivers::testing::DataDir;

std::filesystem::path NebulaDir() { return DataDir() / "velodyne_nebula_rosbag2"; }
std::filesystem::path RustDir() { return DataDir() / "velodyne_ouster_pcaps_rust_lidar_utils"; }
std::filesystem::path Hdl32eCalibration() { return std::filesystem::path(DAMMLOAM_DRIVERS_CALIBRATION_DIR) / "HDL32E.yaml"; }

struct Decoded {
  std::vector<Scan> scans;
  Diagnostics diag;
};

Decoded DecodeCapture(const std::filesystem::path& pcap, const DecoderConfig& config, const Calibration& cal) {
  Decoder decoder(config, cal);
  PcapReader reader(pcap, PcapFilter{2368});
  Decoded out;
  UdpDatagram d;
  while (reader.Next(d)) {
    if (auto s = decoder.Push(d.payload, d.capture_time)) out.scans.push_back(std::move(*s));
  }
  decoder.Flush();
  out.diag = decoder.diagnostics();
  return out;
}

void ExpectWellFormed(const Scan& scan, double period, int rings) {
  ASSERT_TRUE(scan.has_times());
  ASSERT_TRUE(scan.has_rings());
  ASSERT_EQ(scan.intensities.size(), scan.size());
  EXPECT_GE(*std::min_element(scan.times.begin(), scan.times.end()), 0.0f);
  EXPECT_LT(*std::max_element(scan.times.begin(), scan.times.end()), static_cast<float>(period));
  std::set<int> seen(scan.rings.begin(), scan.rings.end());
  // Every ring appears, except that a beam may see nothing (the indoor VLP-16 scene has no
  // returns on its bottom beam, nebula's own cloud neither).
  EXPECT_GE(static_cast<int>(seen.size()), rings - 1);
  EXPECT_GE(*seen.begin(), 0);
  EXPECT_LE(*seen.rbegin(), rings - 1);
  EXPECT_EQ(*seen.begin(), 0);  // the top beam always sees something here
}

// The best match among the decoded scans (the PCD is the scan nebula closed while reading the
// last message; point order and range filters differ, so compare geometry).
testing::NnStats BestMatch(const std::vector<Scan>& scans, const std::vector<Eigen::Vector3d>& expected,
                           std::size_t* points = nullptr) {
  testing::NnStats best;
  for (const auto& s : scans) {
    const auto st = testing::NearestNeighbourStats(s.points, expected);
    if (st.median < best.median) {
      best = st;
      if (points != nullptr) *points = s.size();
    }
  }
  return best;
}

TEST(VelodyneCalibration, ParsesNebulaFilesAndRanksRings) {
  const auto file = NebulaDir() / "calibration" / "VLP16.yaml";
  DAMMLOAM_REQUIRE_DATA(file);
  const Calibration cal = LoadCalibration(file);
  ASSERT_EQ(cal.lasers.size(), 16u);
  EXPECT_DOUBLE_EQ(cal.distance_resolution, 0.002);
  EXPECT_EQ(cal.lasers[15].ring, 0);   // +15 deg, top beam
  EXPECT_EQ(cal.lasers[0].ring, 15);   // -15 deg, bottom beam
  const Calibration hdl = LoadCalibration(Hdl32eCalibration());
  ASSERT_EQ(hdl.lasers.size(), 32u);
  EXPECT_EQ(hdl.lasers[31].ring, 0);   // +10.67 deg
  EXPECT_EQ(hdl.lasers[0].ring, 31);   // -30.67 deg
}

TEST(VelodyneCalibration, ErrorsNameTheProblem) {
  auto message = [](const std::string& yaml) {
    try {
      ParseCalibration(yaml, "c.yaml");
    } catch (const DriverError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("lasers: [").find("c.yaml: not valid YAML"), std::string::npos);
  EXPECT_NE(message("foo: 1").find("'lasers'"), std::string::npos);
  EXPECT_NE(message("lasers:\n  - {laser_id: 0}\n").find("vert_correction"), std::string::npos);
  EXPECT_NE(message("lasers:\n  - {laser_id: 3, vert_correction: 0.1}\n").find("laser_id"), std::string::npos);
  EXPECT_NE(message("lasers:\n  - {laser_id: 0, vert_correction: x}\n").find("not a number"), std::string::npos);
  EXPECT_THROW(Decoder(DecoderConfig{.model = Model::kVLP32C}, ParseCalibration("lasers:\n  - {laser_id: 0, vert_correction: 0.1}\n")),
               DriverError);
}

TEST(VelodyneDecoder, Vlp16DualReturnMatchesNebulaPcd) {
  const auto pcap = NebulaDir() / "vlp16" / "vlp16_packets_from_rosbag2.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const DecoderConfig config{.model = Model::kVLP16, .min_range = 0.3, .max_range = 300.0, .scan_phase_deg = 0.0};
  const Decoded d = DecodeCapture(pcap, config, LoadCalibration(NebulaDir() / "calibration" / "VLP16.yaml"));
  ASSERT_GE(d.scans.size(), 2u) << d.diag.Summary();
  EXPECT_EQ(d.diag.Get("product_id_mismatch"), 0u);
  for (const auto& s : d.scans) ExpectWellFormed(s, 0.1, 16);
  const auto expected = testing::ReadPcdXyz(NebulaDir() / "vlp16" / "1673400472138016708.pcd");
  ASSERT_EQ(expected.size(), 14831u);
  std::size_t points = 0;
  const auto st = BestMatch(d.scans, expected, &points);
  EXPECT_LT(st.median, 0.01);
  EXPECT_GT(st.fraction_within, 0.95);
  EXPECT_NEAR(static_cast<double>(points), 14831.0, 0.1 * 14831.0);
}

TEST(VelodyneDecoder, Vlp32cMatchesNebulaPcd) {
  const auto pcap = NebulaDir() / "vlp32" / "vlp32_packets_from_rosbag2.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  // Nebula's settings for this capture: strongest return, 0.4..50 m, scan phase 180 deg.
  const DecoderConfig config{.model = Model::kVLP32C, .min_range = 0.4, .max_range = 50.0, .scan_phase_deg = 180.0};
  const Decoded d = DecodeCapture(pcap, config, LoadCalibration(NebulaDir() / "calibration" / "VLP32.yaml"));
  ASSERT_GE(d.scans.size(), 2u) << d.diag.Summary();
  for (const auto& s : d.scans) ExpectWellFormed(s, 0.1, 32);
  const auto expected = testing::ReadPcdXyz(NebulaDir() / "vlp32" / "1713492677464078412.pcd");
  ASSERT_EQ(expected.size(), 26216u);
  std::size_t points = 0;
  const auto st = BestMatch(d.scans, expected, &points);
  EXPECT_LT(st.median, 0.01);
  EXPECT_GT(st.fraction_within, 0.95);
  EXPECT_NEAR(static_cast<double>(points), 26216.0, 0.1 * 26216.0);
}

TEST(VelodyneDecoder, Hdl32eDrivingCaptureSplitsIntoRevolutions) {
  const auto pcap = RustDir() / "hdl32e_example.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const Decoded d = DecodeCapture(pcap, DecoderConfig{.model = Model::kHDL32E}, LoadCalibration(Hdl32eCalibration()));
  // 6 azimuth wraps in 0.484 s: 5 complete revolutions; the partial head and tail are dropped.
  ASSERT_EQ(d.scans.size(), 5u) << d.diag.Summary();
  EXPECT_EQ(d.diag.Get("partial_scans"), 2u);
  EXPECT_EQ(d.diag.Get("product_id_mismatch"), 0u);
  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    ExpectWellFormed(d.scans[k], 0.1, 32);
    EXPECT_GT(d.scans[k].size(), 40000u);
    if (k > 0) {
      EXPECT_NEAR(d.scans[k].t_start - d.scans[k - 1].t_start, 1.0 / 11.7, 0.01);  // ~11.7 Hz
    }
  }
}

TEST(VelodyneDecoder, Vlp16WithHdl32eProductIdIsDiagnosedAndDecoded) {
  const auto pcap = RustDir() / "velodyne_vlp16.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const auto cal = LoadCalibration(NebulaDir() / "calibration" / "VLP16.yaml");
  // Cut where the capture's second packet starts so that its ~1.1 revolutions hold a whole scan.
  PcapReader reader(pcap, PcapFilter{2368});
  UdpDatagram first;
  ASSERT_TRUE(reader.Next(first));
  const double phase = (first.payload[2] | (first.payload[3] << 8)) / 100.0 + 5.0;
  const Decoded d = DecodeCapture(pcap, DecoderConfig{.model = Model::kVLP16, .scan_phase_deg = std::fmod(phase, 360.0)}, cal);
  EXPECT_EQ(d.diag.Get("product_id_mismatch"), 84u);
  ASSERT_FALSE(d.diag.messages().empty());
  EXPECT_NE(d.diag.messages()[0].find("0x21"), std::string::npos) << d.diag.messages()[0];
  ASSERT_EQ(d.scans.size(), 1u) << d.diag.Summary();
  ExpectWellFormed(d.scans[0], 0.1, 16);
  EXPECT_GT(d.scans[0].size(), 15000u);
}

TEST(VelodyneDecoder, HalfRevolutionCaptureEmitsNoScan) {
  const auto pcap = RustDir() / "velodyne_vlp32_actually_hdl32e.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const Decoded d = DecodeCapture(pcap, DecoderConfig{.model = Model::kHDL32E}, LoadCalibration(Hdl32eCalibration()));
  EXPECT_TRUE(d.scans.empty());
  EXPECT_GE(d.diag.Get("partial_scans"), 1u);
  EXPECT_EQ(d.diag.Get("packets"), 91u);
}

TEST(VelodyneDecoder, DamagedPacketsAreCountedAndSkipped) {
  const auto pcap = RustDir() / "hdl32e_example.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  Decoder decoder(DecoderConfig{.model = Model::kHDL32E}, LoadCalibration(Hdl32eCalibration()));
  PcapReader reader(pcap);  // no port filter: GPS position packets reach the decoder
  UdpDatagram d;
  std::vector<Scan> scans;
  int n = 0;
  while (reader.Next(d)) {
    ++n;
    if (n % 50 == 7) d.payload.resize(700);                      // truncated
    if (n % 50 == 8 && d.payload.size() == kPacketSize) d.payload[0] = 0x00;  // bad block flag
    if (auto s = decoder.Push(d.payload, d.capture_time)) scans.push_back(std::move(*s));
  }
  decoder.Flush();
  const auto& diag = decoder.diagnostics();
  EXPECT_GE(diag.Get("wrong_size_packets"), 100u);  // 100 position packets + truncated ones
  EXPECT_GE(diag.Get("bad_blocks"), 1u);
  EXPECT_EQ(scans.size(), 5u) << diag.Summary();
  for (const auto& s : scans) ExpectWellFormed(s, 0.1, 32);
}

}  // namespace
}  // namespace dammloam::drivers::velodyne
