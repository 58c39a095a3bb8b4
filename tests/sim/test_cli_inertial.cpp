// dammloam-simulate writes imu.csv (every run) and wheel.csv (wheeled carriers) with their
// meta.json keys, and the scans, times and ground truth are byte for byte those of a run
// without them.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/sequence_io.hpp"
#include "tests/sim/simulate_cli_fixture.hpp"
#include "tests/support/text_file.hpp"

namespace dammloam::sim {
namespace {

namespace fs = std::filesystem;

using SimulateInertialCli = SimulateCliTest;

TEST_F(SimulateInertialCli, StreamsBesideTheScansChangeNothingElse) {
  const fs::path with = dir_ / "with", without = dir_ / "without";
  const std::string common = "--preset wheeled-zigzag --sensor vlp-16 --scans 3 --columns 360 --seed 2 --out ";
  ASSERT_EQ(Run(common + with.string()), 0) << Log();
  EXPECT_NE(Log().find("imu.csv: 31 samples at 100 Hz"), std::string::npos) << Log();
  ASSERT_EQ(Run(common + without.string() + " --no-imu --no-wheel"), 0) << Log();
  EXPECT_NE(Log().find("imu.csv: not written; wheel.csv: not written"), std::string::npos) << Log();

  for (const std::string name : {"times.txt", "gt.tum", "scans/000000.bin", "scans/000002.bin"}) {
    EXPECT_EQ(test::ReadText(with / name), test::ReadText(without / name)) << name;
  }
  EXPECT_FALSE(fs::exists(without / "imu.csv"));
  EXPECT_FALSE(fs::exists(without / "wheel.csv"));
  EXPECT_EQ(test::ReadText(without / "meta.json").find("imu"), std::string::npos);

  const io::SequenceReader reader = io::SequenceReader::Open(with);
  io::StreamReadReport report;
  const auto imu = reader.ReadImu(&report, {/*strict=*/true});
  ASSERT_TRUE(imu);
  ASSERT_EQ(imu->size(), 31u);  // 0.3 s at 100 Hz, both ends
  EXPECT_NEAR(imu->front().t - reader.times().front(), 0.003, 1e-6);  // the clock offset
  // A robot standing at the start, nearly level: gravity on z.
  EXPECT_NEAR(imu->front().linear_acceleration.z(), 9.81, 0.3);
  const auto wheel = reader.ReadWheel(nullptr, {true});
  ASSERT_TRUE(wheel);
  EXPECT_EQ(wheel->size(), 16u);  // 50 Hz
  const io::SequenceMeta& meta = reader.meta();
  ASSERT_TRUE(meta.T_sensor_imu && meta.imu_noise && meta.T_sensor_base);
  EXPECT_NEAR(meta.T_sensor_imu->translation().x(), 0.006253, 1e-12);
  EXPECT_NEAR(meta.T_sensor_base->translation().z(), -0.8, 1e-12);
  EXPECT_DOUBLE_EQ(meta.imu_time_offset, 0.003);

  // A hand-held run gets no wheel odometry.
  ASSERT_EQ(Run("--preset handheld-aggressive --sensor vlp-16 --scans 2 --columns 360 --out " +
                (dir_ / "run").string()),
            0)
      << Log();
  EXPECT_TRUE(fs::exists(dir_ / "run" / "imu.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "run" / "wheel.csv"));
}

}  // namespace
}  // namespace dammloam::sim
