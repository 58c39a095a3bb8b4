// ROS 1 bags (format 2.0): bags written by Debian's python3-rosbag (ROS Noetic's own writer) with
// stored, bz2 and lz4 chunks read back value for value; bags built byte by byte from the format
// specification (tests/bag/ros1_bag_bytes.hpp) for an unindexed bag and every kind of damage.
// dammloam-odometry on them: inputs_odometry_test.cpp.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <chrono>
#include <cstdlib>
#include <fstream>

#include "io/bag/bag_scans.hpp"
#include "io/bag/imu_messages.hpp"
#include "io/motion_csv.hpp"
#include "io/bag/ros1_bag.hpp"
#include "io/bag/scan_source.hpp"
#include "io/io_error.hpp"
#include "tests/bag/inputs_fixture.hpp"
#include "tests/bag/ros1_bag_bytes.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tests/tools/test_support.hpp"

namespace dammloam {
namespace {

namespace fs = std::filesystem;
using test::RosbagMissing;
using test::WriteRosbag;


void WriteBytes(const fs::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string ReadBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<Scan> ReadAll(const fs::path& bag, const std::string& topic = "") {
  io::BagScans scans(bag, {topic, io::RecordedCloudLimits()});
  std::vector<Scan> out;
  while (auto scan = scans.Next()) out.push_back(std::move(*scan));
  return out;
}

TEST(Ros1Bag, RosbagsStoredBz2AndLz4ReadBackValueForValue) {
  if (const std::string why = RosbagMissing(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir tmp;
  const std::vector<Scan> scans = test::TestScans(6, 3000);
  test::WriteSequence(tmp / "seq", scans);
  for (const std::string compression : {"none", "bz2", "lz4"}) {
    SCOPED_TRACE(compression);
    const fs::path bag = tmp / (compression + ".bag");
    WriteRosbag(tmp / "seq", bag, compression);
    io::Ros1Bag reader(bag);
    ASSERT_EQ(reader.topics().size(), 2u);
    for (const io::BagTopic& t : reader.topics()) {
      EXPECT_EQ(t.serialization_format, "ros1");
      EXPECT_EQ(t.message_count, std::optional<std::uint64_t>(6));
      EXPECT_EQ(t.type, t.name == "/points" ? "sensor_msgs/msg/PointCloud2" : "std_msgs/msg/String");
    }
    EXPECT_EQ(reader.Ros1Type("/points"), "sensor_msgs/PointCloud2");
    const std::vector<Scan> read = ReadAll(bag);
    ASSERT_EQ(read.size(), scans.size());
    for (std::size_t s = 0; s < scans.size(); ++s) {
      EXPECT_EQ(read[s].t_start, scans[s].t_start) << "scan " << s;
      ASSERT_EQ(read[s].size(), scans[s].size());
      for (std::size_t i = 0; i < scans[s].size(); ++i) {
        ASSERT_EQ(read[s].points[i], scans[s].points[i]) << "scan " << s << " point " << i;
        ASSERT_EQ(read[s].intensities[i], scans[s].intensities[i]);
        ASSERT_EQ(read[s].times[i], scans[s].times[i]);
        ASSERT_EQ(read[s].rings[i], scans[s].rings[i]);
      }
    }
    // Several chunks: the 6 scans of 72 kB do not fit in one 200 kB chunk.
    const std::string bytes = ReadBytes(bag);
    std::size_t chunks = 0;
    for (auto at = bytes.find(std::string("op=\x05", 4)); at != std::string::npos;
         at = bytes.find(std::string("op=\x05", 4), at + 1)) {
      ++chunks;
    }
    EXPECT_GE(chunks, 2u);
  }
}

// --- bags built byte by byte -----------------------------------------------------------------

std::vector<float> Cloud(int n, float shift) {
  std::vector<float> xyzi;
  for (int i = 0; i < n; ++i) {
    const float a = 0.1f * static_cast<float>(i);
    xyzi.insert(xyzi.end(), {5.0f * std::cos(a) + shift, 5.0f * std::sin(a), 0.01f * static_cast<float>(i % 7), 10.0f});
  }
  return xyzi;
}

std::string TestBag(const std::string& compression = "none", bool indexed = true, int clouds = 4) {
  std::vector<test::Ros1Message> messages;
  for (int s = 0; s < clouds; ++s) {
    messages.push_back({1, 200u + static_cast<std::uint32_t>(s), 0, "\x05\x00\x00\x00hello"});
    messages.push_back({2, 200u + static_cast<std::uint32_t>(s), 5000,
                        test::Ros1PointCloud2(static_cast<std::uint32_t>(s), 200u + static_cast<std::uint32_t>(s), 5000,
                                              Cloud(50, 0.1f * static_cast<float>(s)))});
  }
  return test::BuildRos1Bag({{1, "/chatter", "std_msgs/String"}, {2, "/points", "sensor_msgs/PointCloud2"}}, messages,
                            compression, 3, indexed);
}

TEST(Ros1Bag, BagBuiltFromTheSpecificationIsRead) {
  test::TempDir tmp;
  WriteBytes(tmp / "a.bag", TestBag());
  const std::vector<Scan> scans = ReadAll(tmp / "a.bag");
  ASSERT_EQ(scans.size(), 4u);
  EXPECT_EQ(scans[2].t_start, StampSeconds({202, 5000}));
  EXPECT_EQ(scans[3].size(), 50u);
  EXPECT_FLOAT_EQ(static_cast<float>(scans[3].points[0].x()), 5.3f);
  // Without the index (index_pos 0, as a recording cut off): one pass finds the connections.
  WriteBytes(tmp / "unindexed.bag", TestBag("none", false));
  io::Ros1Bag unindexed(tmp / "unindexed.bag");
  ASSERT_EQ(unindexed.topics().size(), 2u);
  EXPECT_EQ(unindexed.topics()[1].message_count, std::optional<std::uint64_t>(4));
  EXPECT_EQ(ReadAll(tmp / "unindexed.bag").size(), 4u);
  // The scan source tells the kind from the extension.
  EXPECT_EQ(io::OpenScanSource(tmp / "a.bag")->kind(), "ros1 bag");
}

TEST(Ros1Bag, BadInputIsAnErrorNamingFileRecordAndOffset) {
  test::TempDir tmp;
  const fs::path bag = tmp / "bad.bag";
  WriteBytes(bag, TestBag("zstx"));
  EXPECT_IO_ERROR(ReadAll(bag), bag.string() + ": Chunk record at byte 4109: unknown compression 'zstx' (supported: none, bz2, lz4)");

  WriteBytes(bag, "#ROSBAG V1.2\n");
  EXPECT_IO_ERROR(io::Ros1Bag{bag}, bag.string(), "not a ROS 1 bag of format 2.0 (version 1.2");

  // A topic that is not a point cloud.
  WriteBytes(bag, TestBag());
  EXPECT_IO_ERROR(ReadAll(bag, "/chatter"), "topic /chatter is std_msgs/msg/String, not sensor_msgs/msg/PointCloud2");

  // A message whose field count does not fit.
  std::string bytes = TestBag();
  const std::string fields_of_four = std::string("\x01\x00\x00\x00\x32\x00\x00\x00\x04\x00\x00\x00", 12);
  const auto at = bytes.find(fields_of_four);
  ASSERT_NE(at, std::string::npos);
  bytes[at + 8] = '\x7f';
  WriteBytes(bag, bytes);
  EXPECT_IO_ERROR(ReadAll(bag), bag.string() + ": chunk at byte 4109, Message data record at chunk byte",
                  "fields do not fit in the message");

  // Cut anywhere: an error naming the file (never a crash, never a silent short read of a chunk).
  const std::string whole = TestBag();
  int errors = 0;
  for (std::size_t cut = 0; cut < whole.size(); cut += 23) {
    WriteBytes(bag, whole.substr(0, cut));
    const std::string error = test::IoErrorOf([&] { ReadAll(bag); });
    if (error == "<no IoError>") continue;  // a cut at a record boundary of the index section
    ++errors;
    EXPECT_NE(error.find(bag.string()), std::string::npos) << error;
  }
  EXPECT_GT(errors, static_cast<int>(whole.size() / 23) - 3);
  WriteBytes(bag, whole.substr(0, 4109 + 200));  // inside the first chunk
  EXPECT_IO_ERROR(ReadAll(bag), bag.string() + ": Chunk record at byte 4109: truncated: data needs");
}

TEST(Ros1Bag, CorruptCompressedChunksAreErrors) {
  if (const std::string why = RosbagMissing(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir tmp;
  test::WriteSequence(tmp / "seq", test::TestScans(3, 2000));
  for (const std::string compression : {"bz2", "lz4"}) {
    WriteRosbag(tmp / "seq", tmp / "ok.bag", compression);
    std::string bytes = ReadBytes(tmp / "ok.bag");
    const auto chunk = bytes.find("compression=" + compression);
    ASSERT_NE(chunk, std::string::npos);
    for (std::size_t i = 0; i < 64; ++i) bytes[chunk + 400 + i] = static_cast<char>(bytes[chunk + 400 + i] ^ 0x5a);
    WriteBytes(tmp / "bad.bag", bytes);
    EXPECT_IO_ERROR(ReadAll(tmp / "bad.bag"), (tmp / "bad.bag").string() + ": Chunk record at byte 4117", compression);
  }
}

// sensor_msgs/Imu beside the clouds (ouster-ros's /ouster/imu) is read along: every sample of
// the sequence's imu.csv, in order, and the faults a driver emits dropped and counted by reason.
std::vector<ImuSample> TestImu(double t0, int count) {
  std::vector<ImuSample> imu;
  for (int k = 0; k < count; ++k) {
    ImuSample s;
    s.t = t0 + 0.01 * k;
    s.angular_velocity = {0.01 * k, -0.02, 0.3 + 1e-3 * k};
    s.linear_acceleration = {0.1, 0.2 * std::sin(k), 9.81};
    imu.push_back(s);
  }
  return imu;
}

TEST(Ros1Bag, ImuMessagesAreReadAlongWithTheClouds) {
  if (const std::string why = RosbagMissing(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir tmp;
  const std::vector<Scan> scans = test::TestScans(4, 500);
  test::WriteSequence(tmp / "seq", scans);
  const std::vector<ImuSample> imu = TestImu(scans.front().t_start - 0.05, 45);
  io::WriteImuCsv(tmp / "seq" / "imu.csv", imu);
  WriteRosbag(tmp / "seq", tmp / "imu.bag", "lz4");
  const std::optional<io::BagImu> read = io::ReadBagImu(tmp / "imu.bag");
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->topic, "/imu");
  EXPECT_EQ(read->frame_id, "imu");
  EXPECT_EQ(read->report.dropped(), 0u);
  ASSERT_EQ(read->samples.size(), imu.size());
  for (std::size_t k = 0; k < imu.size(); ++k) {
    EXPECT_NEAR(read->samples[k].t, imu[k].t, 1e-6) << k;  // through whole nanoseconds
    EXPECT_EQ(read->samples[k].angular_velocity, imu[k].angular_velocity) << k;
    EXPECT_EQ(read->samples[k].linear_acceleration, imu[k].linear_acceleration) << k;
  }
  // The clouds are unchanged by the IMU messages between them.
  EXPECT_EQ(ReadAll(tmp / "imu.bag").size(), scans.size());

  const auto r = test::RunCommand("/usr/bin/python3 " + (test::BagTestDir() / "write_ros1_bag.py").string() +
                                  " " + (tmp / "seq").string() + " " + (tmp / "faults.bag").string() +
                                  " none imu-faults 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::optional<io::BagImu> faulty = io::ReadBagImu(tmp / "faults.bag", "/imu");
  ASSERT_TRUE(faulty.has_value());
  EXPECT_EQ(faulty->samples.size(), imu.size());
  EXPECT_EQ(faulty->report.duplicate_stamp, 1u);
  EXPECT_EQ(faulty->report.non_finite, 1u);
  EXPECT_NE(faulty->report.Summary().find("duplicate stamp"), std::string::npos) << faulty->report.Summary();

  // No IMU topic: nothing; a named topic that is not sensor_msgs/Imu: an error naming it.
  test::WriteSequence(tmp / "plain", scans);
  WriteRosbag(tmp / "plain", tmp / "plain.bag", "none");
  EXPECT_FALSE(io::ReadBagImu(tmp / "plain.bag").has_value());
  EXPECT_IO_ERROR(io::ReadBagImu(tmp / "plain.bag", "/points"), "no sensor_msgs/msg/Imu topic '/points'");
}

// A measurement, not run by default (--gtest_also_run_disabled_tests): a large bag streams with
// one chunk in memory (2026-11-29: 2.2 GB, 700 clouds, 6.6 ms per cloud, peak RSS 35 MB). DAMMLOAM_LARGE_BAG_MESSAGES clouds of
// 131072 points (OS1-128 size, 3.1 MB each; default 700 = 2.2 GB) written by python3-rosbag.
TEST(Ros1Bag, DISABLED_LargeBagStreamsWithBoundedMemory) {
  if (const std::string why = RosbagMissing(); !why.empty()) GTEST_SKIP() << why;
  const char* env = std::getenv("DAMMLOAM_LARGE_BAG_MESSAGES");
  const int messages = env != nullptr ? std::atoi(env) : 700;
  test::TempDir tmp;
  const fs::path bag = tmp / "large.bag";
  const auto w = test::RunCommand("/usr/bin/python3 " + (test::BagTestDir() / "write_ros1_bag.py").string() +
                                  " --large " + bag.string() + " " + std::to_string(messages) + " 131072 2>&1");
  ASSERT_EQ(w.exit_code, 0) << w.output;
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
  const auto start = std::chrono::steady_clock::now();
  io::BagScans scans(bag, {"", io::RecordedCloudLimits()});
  int n = 0;
  while (auto scan = scans.Next()) {
    ASSERT_EQ(scan->size(), 131072u);
    ++n;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  EXPECT_EQ(n, messages);
  std::cout << fs::file_size(bag) / 1e6 << " MB bag, " << n << " clouds: " << 1e3 * seconds / n
            << " ms per cloud, peak RSS " << after.ru_maxrss / 1024 << " MB (" << before.ru_maxrss / 1024
            << " MB before)\n";
  EXPECT_LT(after.ru_maxrss / 1024, 200);
}

}  // namespace
}  // namespace dammloam
