// dammloam-simulate --preset / --motion round trips.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/sequence_io.hpp"
#include "tests/sim/simulate_cli_fixture.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {
namespace {

namespace fs = std::filesystem;

using SimulatePresetCli = SimulateCliTest;

TEST_F(SimulatePresetCli, PresetPrefixMatchesTheLibrary) {
  const fs::path out = dir_ / "seq";
  ASSERT_EQ(Run("--preset wheeled-corridor --sensor vlp-16 --scans 3 --seed 5 --columns 360 --out " +
                out.string()),
            0)
      << Log();
  EXPECT_NE(Log().find("preset=wheeled-corridor"), std::string::npos) << Log();
  const io::SequenceReader reader = io::SequenceReader::Open(out);
  ASSERT_EQ(reader.size(), 3u);
  SensorSpec sensor = Vlp16();
  sensor.columns = 360;
  const Simulator sim(*FindPreset("wheeled-corridor"), sensor, 5);  // planned: 800 scans
  const auto gt = reader.ReadGroundTruth();
  ASSERT_TRUE(gt.has_value());
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Isometry3d T = sim.PoseAt(sim.ScanStartTime(static_cast<int>(k)));
    EXPECT_LT(((*gt)[k].T.translation() - T.translation()).norm(), 1e-6);
    const Scan expected = sim.SimulateScan(static_cast<int>(k));
    const Scan scan = reader.ReadScan(k);
    ASSERT_EQ(scan.size(), expected.size());
    for (std::size_t i = 0; i < scan.size(); i += 31) {
      ASSERT_LT((scan.points[i] - expected.points[i]).norm(), 1e-4);
    }
  }
}

// Every preset's walk from the CLI is the library's (the benchmark simulates through the
// library): 16 s of each, on a sensor of 2 x 36 rays so that only the motion costs. Until
// 2026-11-29 the CLI dropped handheld-look-around's swings.
TEST_F(SimulatePresetCli, EveryPresetWalksAsInTheLibrary) {
  for (const Preset& preset : Presets()) {
    const fs::path out = dir_ / preset.name;
    ASSERT_EQ(Run("--preset " + preset.name + " --sensor vlp-16 --rings 2 --columns 36 --scans 160 "
                  "--seed 2 --no-imu --no-wheel --out " + out.string()),
              0)
        << Log();
    SensorSpec sensor = Vlp16();
    sensor.columns = 36;
    const Simulator sim(preset, sensor, 2);
    const auto gt = io::SequenceReader::Open(out).ReadGroundTruth();
    ASSERT_TRUE(gt.has_value());
    ASSERT_EQ(gt->size(), 160u);
    double worst = 0.0;
    for (std::size_t k = 0; k < gt->size(); ++k) {
      const Eigen::Isometry3d T = sim.PoseAt(sim.ScanStartTime(static_cast<int>(k)));
      worst = std::max(worst, ((*gt)[k].T.translation() - T.translation()).norm() +
                                  Eigen::AngleAxisd(T.rotation().transpose() * (*gt)[k].T.rotation()).angle());
    }
    EXPECT_LT(worst, 1e-5) << preset.name;
  }
}

// labels/NNNNNN.bin: one byte per point of the scan file, only for runs with actors.
TEST_F(SimulatePresetCli, ActorPresetWritesLabelsBesideTheScans) {
  const fs::path out = dir_ / "seq";
  ASSERT_EQ(Run("--preset follow-me --sensor vlp-16 --scans 3 --out " + out.string()), 0) << Log();
  EXPECT_NE(Log().find("1 leading"), std::string::npos) << Log();
  const io::SequenceReader reader = io::SequenceReader::Open(out);
  ASSERT_EQ(reader.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const fs::path labels = out / "labels" / io::ScanFileName(k);
    ASSERT_TRUE(fs::exists(labels)) << labels;
    EXPECT_EQ(fs::file_size(labels), reader.ReadScan(k).size()) << labels;
    EXPECT_EQ(fs::file_size(labels) * 24, fs::file_size(reader.ScanPath(k))) << labels;
  }
  // The same directory overwritten by a run without actors keeps no stale labels.
  ASSERT_EQ(Run("--preset handheld-corridor --sensor vlp-16 --scans 2 --overwrite --out " + out.string()), 0)
      << Log();
  EXPECT_FALSE(fs::exists(out / "labels"));
  EXPECT_NE(Log().find("actors: none"), std::string::npos) << Log();
}

TEST_F(SimulatePresetCli, MotionOnAnyScene) {
  const fs::path out = dir_ / "seq";
  ASSERT_EQ(Run("--scene corridor --motion legged --scans 3 --columns 256 --out " + out.string()), 0)
      << Log();
  EXPECT_NE(Log().find("noise=0.015"), std::string::npos) << Log();
  EXPECT_NE(Log().find("range=realistic"), std::string::npos) << Log();
  EXPECT_EQ(io::SequenceReader::Open(out).size(), 3u);
}

TEST_F(SimulatePresetCli, HelpListsPresetsMotionsAndScenes) {
  ASSERT_EQ(Run("--help"), 0);
  for (const std::string& name : PresetNames()) EXPECT_NE(Log().find(name), std::string::npos) << name;
  for (const std::string& name : MotionNames()) EXPECT_NE(Log().find(name), std::string::npos) << name;
  EXPECT_NE(Log().find("endless-corridor"), std::string::npos);
}

TEST_F(SimulatePresetCli, BadCombinationsFail) {
  EXPECT_NE(Run("--preset nowhere --out " + (dir_ / "a").string()), 0);
  EXPECT_NE(Log().find("nowhere"), std::string::npos) << Log();
  EXPECT_NE(Run("--preset legged-tunnel --scene corridor --out " + (dir_ / "b").string()), 0);
  EXPECT_NE(Run("--scene corridor --out " + (dir_ / "c").string()), 0);  // no --scans
  EXPECT_NE(Log().find("--scans"), std::string::npos) << Log();
  EXPECT_NE(Run("--out " + (dir_ / "d").string()), 0);  // neither scene nor preset
  EXPECT_NE(Run("--scene corridor --scans 2 --motion flying --out " + (dir_ / "e").string()), 0);
}

}  // namespace
}  // namespace dammloam::sim
