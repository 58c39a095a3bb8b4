#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "reference_cloud.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/text_file.hpp"

namespace dammloam::drivers::velodyne {
namespace {

using test::DataDir;

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

// The packet format fixes the distance unit: a calibration that contradicts it is reported with
// its file name and both values, and the model's unit is used.
TEST(VelodyneCalibration, ContradictingDistanceUnitIsReportedAndIgnored) {
  std::string yaml = test::ReadText(Hdl32eCalibration());
  yaml.erase(yaml.find("distance_resolution:"));  // the file's own (last) line, replaced below
  const Decoder agreeing(DecoderConfig{.model = Model::kHDL32E}, ParseCalibration(yaml + "distance_resolution: 0.002\n", "hdl.yaml"));
  EXPECT_EQ(agreeing.diagnostics().Get("calibration_unit_ignored"), 0u);
  const Decoder contradicting(DecoderConfig{.model = Model::kHDL32E}, ParseCalibration(yaml + "distance_resolution: 0.004\n", "hdl.yaml"));
  ASSERT_EQ(contradicting.diagnostics().Get("calibration_unit_ignored"), 1u);
  const std::string& m = contradicting.diagnostics().messages().front();
  for (const char* part : {"hdl.yaml", "0.004 m", "0.002 m"}) EXPECT_NE(m.find(part), std::string::npos) << m;
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

std::filesystem::path Vls128Pcap() { return NebulaDir() / "vls128" / "vls128_packets_from_rosbag2.pcap"; }

// The real VLS-128 street capture (strongest return, laser 82 dead), decoded with nebula's
// calibration file as shipped: it says 7 mm per count where the packet unit is 4 mm.
Decoded DecodeVls128(Vls128Azimuth azimuth) {
  const DecoderConfig config{.model = Model::kVLS128, .min_range = 0.3, .max_range = 300.0, .scan_phase_deg = 0.0,
                             .vls128_azimuth = azimuth};
  return DecodeCapture(Vls128Pcap(), config, LoadCalibration(NebulaDir() / "calibration" / "VLS128.yaml"));
}

std::size_t RingCount(const Scan& scan) { return std::set<int>(scan.rings.begin(), scan.rings.end()).size(); }

TEST(VelodyneDecoder, Vls128WithNebulasAzimuthsMatchesNebulaPcd) {
  DAMMLOAM_REQUIRE_DATA(Vls128Pcap());
  const Decoded d = DecodeVls128(Vls128Azimuth::kNebula);
  ASSERT_GE(d.scans.size(), 2u) << d.diag.Summary();
  EXPECT_EQ(d.diag.Get("product_id_mismatch") + d.diag.Get("bad_blocks"), 0u) << d.diag.Summary();
  // The file's 7 mm is reported and the packet's 4 mm used.
  ASSERT_EQ(d.diag.Get("calibration_unit_ignored"), 1u);
  const std::string& warning = d.diag.messages().front();
  for (const char* part : {"VLS128.yaml", "0.007 m", "0.004 m"}) {
    EXPECT_NE(warning.find(part), std::string::npos) << warning;
  }
  const auto expected = testing::ReadPcdXyz(NebulaDir() / "vls128" / "1585897255376374245.pcd");
  ASSERT_EQ(expected.size(), 208680u);
  std::size_t points = 0;
  const auto st = BestMatch(d.scans, expected, &points);
  EXPECT_LT(st.median, 0.003);
  EXPECT_GE(st.fraction_within, 0.90);
  EXPECT_NEAR(static_cast<double>(points), 208680.0, 0.02 * 208680.0);
  // Laser 82 never returns: 127 rings carry points, in every scan, and no garbage on its ring.
  const int dead_ring = LoadCalibration(NebulaDir() / "calibration" / "VLS128.yaml").lasers[82].ring;
  for (const auto& s : d.scans) {
    EXPECT_EQ(RingCount(s), 127u);
    EXPECT_EQ(std::count(s.rings.begin(), s.rings.end(), dead_ring), 0);
    ExpectWellFormed(s, 0.1, 128);
  }
}

// With the manual's firing-time azimuths (the default) every point is nebula's point turned about
// z by the rotation until its laser fired: at most 0.8 of one sequence's ~0.2 deg, never backwards
// (beyond nebula's rounding to 0.01 deg). Range and height are the same.
TEST(VelodyneDecoder, Vls128FiringTimeAzimuthsDifferFromNebulasOnlyByTheSweep) {
  DAMMLOAM_REQUIRE_DATA(Vls128Pcap());
  const Decoded manual = DecodeVls128(Vls128Azimuth::kFiringTime);
  const Decoded nebula = DecodeVls128(Vls128Azimuth::kNebula);
  ASSERT_EQ(manual.scans.size(), nebula.scans.size());
  for (std::size_t k = 0; k < manual.scans.size(); ++k) {
    const Scan& a = manual.scans[k];
    const Scan& b = nebula.scans[k];
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(RingCount(a), 127u);
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_NEAR(a.points[i].norm(), b.points[i].norm(), 1e-6) << "point " << i;
      ASSERT_NEAR(a.points[i].z(), b.points[i].z(), 1e-6) << "point " << i;
      const double turn_deg = std::remainder(std::atan2(-a.points[i].y(), a.points[i].x()) -
                                                 std::atan2(-b.points[i].y(), b.points[i].x()),
                                             2.0 * M_PI) * 180.0 / M_PI;
      ASSERT_GT(turn_deg, -0.0051) << "point " << i;
      ASSERT_LT(turn_deg, 0.8 * 0.21 + 0.0051) << "point " << i;
    }
  }
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
