// imu.csv, wheel.csv and the meta.json keys that go with them (sequence.md): exact round trips,
// a clear IoError for every malformed file, and every unusable sample dropped and counted with
// its reason and line (or an IoError under strict).
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>

#include "io/sequence_io.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tests/tools/test_support.hpp"

namespace dammloam::io {
namespace {

using test::IoErrorOf;
using test::TempDir;
using test::WriteText;

constexpr const char* kImuHeader = "t,wx,wy,wz,ax,ay,az\n";
// Eigen's `{}` leaves a vector uninitialized: spell zero out.
const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

TEST(MotionCsv, ImuRoundTripIsExact) {
  TempDir tmp;
  std::vector<ImuSample> samples;
  for (int k = 0; k < 5; ++k) {
    const double t = 1700000000.0 + 0.01 * k + 1e-7 * k * k;
    samples.push_back({t, {0.1 * k, -1.0 / 3.0, 1e-9}, {0.0, std::sqrt(2.0), 9.81 + k}});
  }
  WriteImuCsv(tmp / "imu.csv", samples);
  StreamReadReport report;
  const std::vector<ImuSample> back = ReadImuCsv(tmp / "imu.csv", &report);
  ASSERT_EQ(back.size(), samples.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].t, samples[i].t);
    EXPECT_EQ(back[i].angular_velocity, samples[i].angular_velocity);
    EXPECT_EQ(back[i].linear_acceleration, samples[i].linear_acceleration);
  }
  EXPECT_EQ(report.kept, 5u);
  EXPECT_EQ(report.dropped(), 0u);
  EXPECT_EQ(report.Summary(), "");
}

TEST(MotionCsv, WheelRoundTripIsExact) {
  TempDir tmp;
  const std::vector<WheelSample> samples = {{10.0, {0.5, 0.0, 0.0}, {0.0, 0.0, -0.25}},
                                            {10.02, {0.51, 1e-3, 0.0}, {0.0, 0.0, 1.0 / 7.0}}};
  WriteWheelCsv(tmp / "wheel.csv", samples);
  EXPECT_EQ(test::ReadText(tmp / "wheel.csv").substr(0, 20), "t,vx,vy,vz,wx,wy,wz\n");
  const std::vector<WheelSample> back = ReadWheelCsv(tmp / "wheel.csv");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].t, 10.02);
  EXPECT_EQ(back[1].linear_velocity, samples[1].linear_velocity);
  EXPECT_EQ(back[1].angular_velocity, samples[1].angular_velocity);
}

TEST(MotionCsv, WriterRefusesWhatAReaderWouldDrop) {
  TempDir tmp;
  EXPECT_IO_ERROR(WriteImuCsv(tmp / "imu.csv", {{1.0, kZero, kZero}, {1.0, kZero, kZero}}), "imu.csv",
                  "sample 1", "not after");
  ImuSample bad{2.0, kZero, kZero};
  bad.linear_acceleration.z() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_IO_ERROR(WriteImuCsv(tmp / "imu.csv", {bad}), "imu.csv", "sample 0", "not finite");
}

// Malformed files are rejected with file and line.
TEST(MotionCsv, MalformedFilesAreRejectedNamingFileAndLine) {
  TempDir tmp;
  const auto file = tmp / "imu.csv";
  const auto read = [&] { ReadImuCsv(file); };
  EXPECT_IO_ERROR(read(), "imu.csv", "cannot open");
  WriteText(file, "");
  EXPECT_IO_ERROR(read(), "imu.csv", "empty", "t,wx,wy,wz,ax,ay,az");
  WriteText(file, "t,vx,vy,vz,wx,wy,wz\n1,0,0,0,0,0,9.81\n");  // a wheel file given as IMU
  EXPECT_IO_ERROR(read(), "imu.csv:1:", "header must be 't,wx,wy,wz,ax,ay,az'");
  WriteText(file, std::string(kImuHeader) + "1,0,0,0,0,0,9.81\n2,0,0,0,0,9.81\n");
  EXPECT_IO_ERROR(read(), "imu.csv:3:", "has 6 fields, expected 7");
  WriteText(file, std::string(kImuHeader) + "1,0,0,0,0,0,9.81,5\n");
  EXPECT_IO_ERROR(read(), "imu.csv:2:", "has 8 fields, expected 7");
  WriteText(file, std::string(kImuHeader) + "1,0,0,zero,0,0,9.81\n");
  EXPECT_IO_ERROR(read(), "imu.csv:2:", "field 4 'zero' is not a number");
  WriteText(file, std::string(kImuHeader) + "1,0,0,,0,0,9.81\n");
  EXPECT_IO_ERROR(read(), "imu.csv:2:", "field 4", "not a number");
  WriteText(tmp / "wheel.csv", "t,vx,vy,vz,wx,wy,wz\n1;0;0;0;0;0;0\n");
  EXPECT_IO_ERROR(ReadWheelCsv(tmp / "wheel.csv"), "wheel.csv:2:", "has 1 fields");
}

// Each kind of unusable sample: dropped, counted under its reason, listed with its line; the
// samples around it are kept. Blank lines and CRLF line ends are accepted.
TEST(MotionCsv, UnusableSamplesAreDroppedAndCountedByReason) {
  TempDir tmp;
  const auto file = tmp / "imu.csv";
  WriteText(file, std::string(kImuHeader) +
                      "1.00,0,0,0,0,0,9.81\r\n"  // 2 kept
                      "1.01,nan,0,0,0,0,9.81\n"  // 3 NaN
                      "1.02,0,0,0,0,0,inf\n"     // 4 inf
                      "\n"                        // 5 blank
                      "1.03,0,0,0,0,0,9.81\n"    // 6 kept
                      "1.03,0,0,0,0,0,9.81\n"    // 7 duplicate
                      "1.02,0,0,0,0,0,9.81\n"    // 8 backwards
                      "1.04,0,0,0,0,0,-inf\n"    // 9 inf
                      "1.05,0,0,0,0,0,9.81\n");  // 10 kept
  StreamReadReport report;
  const std::vector<ImuSample> samples = ReadImuCsv(file, &report);
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_EQ(samples[0].t, 1.00);
  EXPECT_EQ(samples[1].t, 1.03);
  EXPECT_EQ(samples[2].t, 1.05);
  EXPECT_EQ(report.kept, 3u);
  EXPECT_EQ(report.non_finite, 3u);
  EXPECT_EQ(report.duplicate_stamp, 1u);
  EXPECT_EQ(report.out_of_order, 1u);
  ASSERT_EQ(report.first_dropped.size(), 5u);
  const int lines[] = {3, 4, 7, 8, 9};
  const SampleFault faults[] = {SampleFault::kNonFinite, SampleFault::kNonFinite,
                                SampleFault::kDuplicateStamp, SampleFault::kOutOfOrderStamp,
                                SampleFault::kNonFinite};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(report.first_dropped[i].line, lines[i]) << i;
    EXPECT_EQ(report.first_dropped[i].fault, faults[i]) << i;
  }
  EXPECT_EQ(report.Summary(),
            "dropped 5: 3 NaN/inf value, 1 duplicate stamp, 1 stamp before the previous one "
            "(first at line 3: NaN/inf value)");
}

TEST(MotionCsv, StrictTurnsTheFirstUnusableSampleIntoAnError) {
  TempDir tmp;
  const auto file = tmp / "wheel.csv";
  StreamReadOptions strict;
  strict.strict = true;
  WriteText(file, "t,vx,vy,vz,wx,wy,wz\n1,0.5,0,0,0,0,0\n1,0.5,0,0,0,0,0\n");
  EXPECT_IO_ERROR(ReadWheelCsv(file, nullptr, strict), "wheel.csv:3:", "duplicate stamp 1 after 1");
  WriteText(file, "t,vx,vy,vz,wx,wy,wz\n2,0.5,0,0,0,0,0\n1,0.5,0,0,0,0,0\n");
  EXPECT_IO_ERROR(ReadWheelCsv(file, nullptr, strict), "wheel.csv:3:", "stamp before the previous one");
  WriteText(file, "t,vx,vy,vz,wx,wy,wz\n1,nan,0,0,0,0,0\n");
  EXPECT_IO_ERROR(ReadWheelCsv(file, nullptr, strict), "wheel.csv:2:", "NaN/inf value in '1,nan");
  // Without strict the same file reads, empty, with the fault counted.
  StreamReadReport report;
  EXPECT_TRUE(ReadWheelCsv(file, &report).empty());
  EXPECT_EQ(report.non_finite, 1u);
}

constexpr const char* kMetaBase =
    R"("sensor": "os1-64", "rings": 2, "columns": 8, "scan_period": 0.1)";

TEST(MetaInertialKeys, RoundTripAndDefaults) {
  TempDir tmp;
  SequenceMeta meta;
  meta.sensor = "os1-64";
  meta.model.rings = 2;
  meta.model.columns = 8;
  meta.model.scan_period = 0.1;
  meta.model.vertical_angles_deg = {1.0, -1.0};
  Eigen::Isometry3d T_imu = OusterOs1ImuToSensor();
  T_imu.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  meta.T_sensor_imu = T_imu;
  meta.imu_noise = ImuNoise{};
  meta.imu_noise->gyro_noise_density = 1.5e-4;
  meta.imu_time_offset = -0.004;
  Eigen::Isometry3d T_base = Eigen::Isometry3d::Identity();
  T_base.translation().z() = -0.8;
  meta.T_sensor_base = T_base;
  WriteMeta(tmp / "meta.json", meta);
  const SequenceMeta back = ReadMeta(tmp / "meta.json");
  ASSERT_TRUE(back.T_sensor_imu && back.imu_noise && back.T_sensor_base);
  EXPECT_TRUE(back.T_sensor_imu->isApprox(T_imu, 1e-12));
  EXPECT_TRUE(back.T_sensor_base->isApprox(T_base, 1e-12));
  EXPECT_EQ(back.imu_noise->gyro_noise_density, 1.5e-4);
  EXPECT_EQ(back.imu_noise->accel_noise_density, ImuNoise{}.accel_noise_density);
  EXPECT_EQ(back.imu_time_offset, -0.004);

  // Without the keys nothing is set, and the file has none of them (old meta.json unchanged).
  SequenceMeta plain = meta;
  plain.T_sensor_imu.reset();
  plain.imu_noise.reset();
  plain.T_sensor_base.reset();
  WriteMeta(tmp / "plain.json", plain);
  EXPECT_EQ(test::ReadText(tmp / "plain.json").find("imu"), std::string::npos);
  const SequenceMeta none = ReadMeta(tmp / "plain.json");
  EXPECT_FALSE(none.T_sensor_imu || none.imu_noise || none.T_sensor_base);

  // The format document's own example; a partial "imu" keeps the other defaults.
  WriteText(tmp / "doc.json", std::string("{") + kMetaBase +
                                  R"(, "imu_extrinsic": {"T_sensor_imu": {"translation": [0.006253, -0.011775, 0.007645],
                                  "quaternion_xyzw": [0, 0, 0, 1]}}, "imu": {"accel_noise_density_m_s2_sqrtHz": 0.002}})");
  const SequenceMeta doc = ReadMeta(tmp / "doc.json");
  ASSERT_TRUE(doc.T_sensor_imu && doc.imu_noise);
  EXPECT_TRUE(doc.T_sensor_imu->isApprox(OusterOs1ImuToSensor()));
  EXPECT_EQ(doc.imu_noise->accel_noise_density, 0.002);
  EXPECT_EQ(doc.imu_noise->gyro_noise_density, ImuNoise{}.gyro_noise_density);
}

TEST(MetaInertialKeys, BadValuesNameTheKey) {
  TempDir tmp;
  const auto file = tmp / "meta.json";
  auto with = [&](const std::string& extra) { WriteText(file, std::string("{") + kMetaBase + ", " + extra + "}"); };
  with(R"("imu_extrinsic": {"T_sensor_imu": {"translation": [0, 0], "quaternion_xyzw": [0, 0, 0, 1]}})");
  EXPECT_IO_ERROR(ReadMeta(file), "meta.json", "imu_extrinsic.T_sensor_imu.translation", "3 numbers");
  with(R"("imu_extrinsic": {"T_sensor_imu": {"translation": [0, 0, 0], "quaternion_xyzw": [0, 0, 0, 2]}})");
  EXPECT_IO_ERROR(ReadMeta(file), "imu_extrinsic.T_sensor_imu.quaternion_xyzw", "not a unit quaternion");
  with(R"("imu_extrinsic": {"T_sensor_imu": {"translation": [0, 0, 0]}})");
  EXPECT_IO_ERROR(ReadMeta(file), "missing required key \"imu_extrinsic.T_sensor_imu.quaternion_xyzw\"");
  with(R"("base_extrinsic": {"T_base": {}})");
  EXPECT_IO_ERROR(ReadMeta(file), "\"base_extrinsic\" must hold an object \"T_sensor_base\"");
  with(R"("imu": {"gyro_noise_density_rad_s_sqrtHz": -1})");
  EXPECT_IO_ERROR(ReadMeta(file), "imu.gyro_noise_density_rad_s_sqrtHz", ">= 0");
  with(R"("imu": {"time_offset_s": "3 ms"})");
  EXPECT_IO_ERROR(ReadMeta(file), "imu.time_offset_s", "seconds");
}

TEST(SequenceStreams, ReaderFindsThemAndOverwriteRemovesThem) {
  TempDir tmp;
  SequenceMeta meta;
  meta.sensor = "test";
  meta.model.rings = 1;
  meta.model.columns = 4;
  meta.model.scan_period = 0.1;
  meta.model.vertical_angles_deg = {0.0};
  {
    SequenceWriter writer(tmp.path(), meta);
    Scan scan;
    scan.t_start = 5.0;
    scan.points = {Eigen::Vector3d(1, 0, 0)};
    scan.intensities = {1.0f};
    scan.times = {0.0f};
    scan.rings = {0};
    writer.Write(scan);
    EXPECT_FALSE(SequenceReader::Open(tmp.path()).ReadImu());
    writer.WriteImu({{5.0, kZero, {0, 0, 9.81}}, {5.01, kZero, {0, 0, 9.81}}});
    writer.WriteWheel({{5.0, {0.5, 0, 0}, kZero}});
  }
  const SequenceReader reader = SequenceReader::Open(tmp.path());
  StreamReadReport report;
  const auto imu = reader.ReadImu(&report);
  ASSERT_TRUE(imu);
  EXPECT_EQ(imu->size(), 2u);
  EXPECT_EQ(report.kept, 2u);
  ASSERT_TRUE(reader.ReadWheel());
  EXPECT_EQ(reader.ReadWheel()->front().linear_velocity.x(), 0.5);
  // A new sequence written over it must not inherit the old streams.
  SequenceWriter again(tmp.path(), meta, /*overwrite=*/true);
  EXPECT_FALSE(std::filesystem::exists(tmp / "imu.csv"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "wheel.csv"));
}

}  // namespace
}  // namespace dammloam::io
