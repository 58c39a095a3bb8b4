// Bags written by programs that are not ours, read by io/bag: MCAP from @mcap/core (node) in
// every compression, CDR byte order and driver field layout, rosbag2 directories with mcap
// storage (node) and sqlite3 storage (Python's sqlite3), and every scan compared with the scan
// it was made from.
#include <gtest/gtest.h>

#include "io/bag/bag_scans.hpp"
#include "io/bag/scan_source.hpp"
#include "tests/bag/bag_fixture.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace dammloam {
namespace {

using test::RunNode;

class BagRead : public ::testing::Test {
 protected:
  void SetUp() override {
    scans_ = test::TestScans(4, 300);
    test::WriteSequence(tmp_ / "seq", scans_);
  }
  // Writes tmp/<name> with write_mcap.cjs; `options` is the JSON body after sequence and out.
  std::filesystem::path WriteMcap(const std::string& name, const std::string& options) {
    const std::filesystem::path out = tmp_ / name;
    std::filesystem::create_directories(out.parent_path());
    RunNode("write_mcap.cjs", "{\"sequence\": \"" + (tmp_ / "seq").string() + "\", \"out\": \"" +
                                  out.string() + "\"" + (options.empty() ? "" : ", ") + options +
                                  "}");
    return out;
  }
  std::vector<Scan> ReadAll(const std::filesystem::path& path, const std::string& topic = "") {
    io::BagScans bag(path, {topic, io::RecordedCloudLimits()});
    std::vector<Scan> out;
    while (auto scan = bag.Next()) out.push_back(std::move(*scan));
    return out;
  }
  // Exact: points, intensities, float times, rings and the stamp as the sequence has them.
  void ExpectSameScans(const std::vector<Scan>& read) {
    ASSERT_EQ(read.size(), scans_.size());
    for (std::size_t s = 0; s < read.size(); ++s) {
      const Scan& a = read[s];
      const Scan& b = scans_[s];
      EXPECT_EQ(a.t_start, b.t_start) << "scan " << s;
      ASSERT_EQ(a.size(), b.size()) << "scan " << s;
      ASSERT_TRUE(a.has_times() && a.has_rings());
      ASSERT_EQ(a.intensities.size(), a.size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a.points[i], b.points[i]) << "scan " << s << " point " << i;
        ASSERT_EQ(a.times[i], b.times[i]) << "scan " << s << " point " << i;
        ASSERT_EQ(a.rings[i], b.rings[i]) << "scan " << s << " point " << i;
        ASSERT_EQ(a.intensities[i], b.intensities[i]) << "scan " << s << " point " << i;
      }
    }
  }
  // Driver layouts that store times in integer nanoseconds or intensity in a byte.
  void ExpectCloseScans(const std::vector<Scan>& read, bool byte_intensity) {
    ASSERT_EQ(read.size(), scans_.size());
    for (std::size_t s = 0; s < read.size(); ++s) {
      const Scan& a = read[s];
      const Scan& b = scans_[s];
      EXPECT_NEAR(a.t_start, b.t_start, 1e-9) << "scan " << s;
      ASSERT_EQ(a.size(), b.size());
      ASSERT_TRUE(a.has_times() && a.has_rings());
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a.points[i], b.points[i]) << "scan " << s << " point " << i;
        ASSERT_NEAR(a.times[i], b.times[i], 2e-9) << "scan " << s << " point " << i;
        ASSERT_EQ(a.rings[i], b.rings[i]) << "scan " << s << " point " << i;
        ASSERT_NEAR(a.intensities[i], b.intensities[i], byte_intensity ? 0.5 : 0.0);
      }
    }
  }

  test::TempDir tmp_;
  std::vector<Scan> scans_;
};

TEST_F(BagRead, McapZstdChunksLittleEndianGiveTheSequenceScansExactly) {
  DAMMLOAM_REQUIRE_NODE();
  ExpectSameScans(ReadAll(WriteMcap("a.mcap", R"("compression": "zstd")")));
}

TEST_F(BagRead, McapLz4ChunksBigEndianCdr) {
  DAMMLOAM_REQUIRE_NODE();
  ExpectSameScans(ReadAll(WriteMcap("a.mcap", R"("compression": "lz4", "endian": "big")")));
}

TEST_F(BagRead, McapWithoutChunksOrSummaryIsScannedForItsChannels) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = WriteMcap("a.mcap", R"("chunked": false, "summary": false, "compression": "none")");
  ExpectSameScans(ReadAll(file));
}

TEST_F(BagRead, VelodyneLayoutStampedAtTheEndOfTheSweepIsMovedToTheFirstPoint) {
  DAMMLOAM_REQUIRE_NODE();
  const auto read = ReadAll(WriteMcap("a.mcap", R"("layout": "velodyne", "stamp": "end")"));
  ASSERT_EQ(read.size(), scans_.size());
  for (std::size_t s = 0; s < read.size(); ++s) {
    EXPECT_NEAR(read[s].t_start, scans_[s].t_start, 1e-6);
    EXPECT_EQ(*std::min_element(read[s].times.begin(), read[s].times.end()), 0.0f);
    EXPECT_NEAR(read[s].times.back(), scans_[s].times.back(), 1e-6);
    EXPECT_EQ(read[s].rings, scans_[s].rings);
  }
}

TEST_F(BagRead, OusterOrganisedCloudWithNanosecondTimes) {
  DAMMLOAM_REQUIRE_NODE();
  ExpectCloseScans(ReadAll(WriteMcap("a.mcap", R"("layout": "ouster", "compression": "none")")),
                   false);
}

TEST_F(BagRead, NebulaLayoutWithChannelAndByteIntensity) {
  DAMMLOAM_REQUIRE_NODE();
  ExpectCloseScans(ReadAll(WriteMcap("a.mcap", R"("layout": "nebula")")), true);
}

TEST_F(BagRead, TopicIsPickedByNameAndOtherTopicsAreSkipped) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = WriteMcap("a.mcap", R"("extra": true)");
  ExpectSameScans(ReadAll(file, "/points"));
  // The rear cloud is the same scan mirrored in x.
  const auto rear = ReadAll(file, "/points_rear");
  ASSERT_EQ(rear.size(), scans_.size());
  EXPECT_EQ(rear[1].points[7].x(), -scans_[1].points[7].x());
}

TEST_F(BagRead, AmbiguousMissingOrWrongTopicIsAClearError) {
  DAMMLOAM_REQUIRE_NODE();
  const auto file = WriteMcap("a.mcap", R"("extra": true)");
  const auto error = [&](const std::string& topic) {
    try {
      io::BagScans bag(file, {topic, io::RecordedCloudLimits()});
    } catch (const io::IoError& e) {
      return std::string(e.what());
    }
    return std::string("<no error>");
  };
  const std::string ambiguous = error("");
  EXPECT_NE(ambiguous.find("2 sensor_msgs/msg/PointCloud2 topics: pick one with --topic"),
            std::string::npos) << ambiguous;
  EXPECT_NE(ambiguous.find("/points_rear (sensor_msgs/msg/PointCloud2, 4 messages)"),
            std::string::npos) << ambiguous;
  EXPECT_NE(ambiguous.find(file.string()), std::string::npos) << ambiguous;
  const std::string not_cloud = error("/chatter");
  EXPECT_NE(not_cloud.find("topic /chatter is std_msgs/msg/String, not sensor_msgs/msg/PointCloud2"),
            std::string::npos) << not_cloud;
  const std::string missing = error("/nope");
  EXPECT_NE(missing.find("no topic /nope (topics: "), std::string::npos) << missing;
}

TEST_F(BagRead, Rosbag2WithMcapStorage) {
  DAMMLOAM_REQUIRE_NODE();
  WriteMcap("bag/bag_0.mcap", R"("rosbag2": true, "extra": true)");
  ExpectSameScans(ReadAll(tmp_ / "bag", "/points"));
}

TEST_F(BagRead, Rosbag2WithSqliteStorageFromPython) {
  const auto r = test::RunCommand("python3 " + (test::BagTestDir() / "write_rosbag2_sqlite.py").string() +
                                  " " + (tmp_ / "seq").string() + " " + (tmp_ / "bag").string() + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ExpectSameScans(ReadAll(tmp_ / "bag"));
  // The scan source reads the size from metadata.yaml and the model from --sensor-meta.
  const auto source = io::OpenScanSource(tmp_ / "bag", {"", tmp_ / "seq" / "meta.json"});
  EXPECT_EQ(source->kind(), "rosbag2");
  EXPECT_EQ(source->size(), std::optional<std::size_t>(4));
  EXPECT_EQ(source->model().rings, 16);
  EXPECT_EQ(source->model().columns, 100);
}

TEST_F(BagRead, Rosbag2WithZstdCompressedMessages) {
  DAMMLOAM_REQUIRE_NODE();
  const auto r = test::RunCommand("python3 " + (test::BagTestDir() / "write_rosbag2_sqlite.py").string() +
                                  " " + (tmp_ / "seq").string() + " " + (tmp_ / "bag").string() +
                                  " --zstd-messages 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_NE(test::ReadText(tmp_ / "bag" / "metadata.yaml").find("compression_mode: \"MESSAGE\""),
            std::string::npos);
  ExpectSameScans(ReadAll(tmp_ / "bag"));
}

TEST(GuessSensorModel, FromRingsPointsAndStamps) {
  const auto scans = test::TestScans(2, 320);
  const SensorModel m = io::GuessSensorModel(scans[0], 320, 1, &scans[1]);
  EXPECT_EQ(m.rings, 16);
  EXPECT_EQ(m.columns, 20);
  EXPECT_NEAR(m.scan_period, 0.1, 1e-9);
  EXPECT_EQ(io::GuessSensorModel(scans[0], 2048 * 64, 64, nullptr).columns, 2048);
}

}  // namespace
}  // namespace dammloam
