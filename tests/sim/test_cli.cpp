#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/sequence_io.hpp"
#include "tests/sim/simulate_cli_fixture.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {
namespace {

namespace fs = std::filesystem;

using SimulateCli = SimulateCliTest;

TEST_F(SimulateCli, WritesASequenceThatReadsBackAsTheSimulatedScans) {
  const fs::path out = dir_ / "seq";
  ASSERT_EQ(Run("--scene zigzag --sensor vlp-16 --scans 4 --seed 3 --noise 0.01 --out " + out.string()), 0)
      << Log();
  EXPECT_NE(Log().find("ms/scan"), std::string::npos) << Log();

  const io::SequenceReader reader = io::SequenceReader::Open(out);
  ASSERT_EQ(reader.size(), 4u);
  EXPECT_EQ(reader.meta().sensor, "vlp-16");
  EXPECT_EQ(reader.meta().model.rings, 16);
  EXPECT_EQ(reader.meta().model.columns, 1800);
  ASSERT_EQ(reader.meta().model.vertical_angles_deg.size(), 16u);
  EXPECT_NEAR(reader.meta().model.vertical_angles_deg[0], 15.0, 1e-9);

  SimOptions options;
  options.seed = 3;
  options.noise_sigma = 0.01;
  options.num_scans = 4;
  const Simulator sim(SceneKind::Zigzag, Vlp16(), options);
  const auto gt = reader.ReadGroundTruth();
  ASSERT_TRUE(gt.has_value());
  ASSERT_EQ(gt->size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const Scan expected = sim.SimulateScan(static_cast<int>(k));
    const Scan scan = reader.ReadScan(k);
    EXPECT_NEAR(reader.times()[k], expected.t_start, 1e-6);
    ASSERT_EQ(scan.size(), expected.size());
    for (std::size_t i = 0; i < scan.size(); i += 97) {
      ASSERT_LT((scan.points[i] - expected.points[i]).norm(), 1e-4) << "scan " << k << " point " << i;
      ASSERT_EQ(scan.rings[i], expected.rings[i]);
      ASSERT_NEAR(scan.times[i], expected.times[i], 1e-7);
    }
    const Eigen::Isometry3d T = sim.PoseAt(expected.t_start);
    EXPECT_NEAR((*gt)[k].t, expected.t_start, 1e-6);
    EXPECT_LT(((*gt)[k].T.translation() - T.translation()).norm(), 1e-6);
    EXPECT_LT(((*gt)[k].T.linear() - T.linear()).norm(), 1e-6);
  }
}

TEST_F(SimulateCli, SensorOverridesReachMetaJson) {
  const fs::path out = dir_ / "seq";
  ASSERT_EQ(Run("--scene corridor --scans 2 --rings 32 --columns 256 --vfov-up 10 --vfov-down -20 "
                "--threads 1 --out " + out.string()),
            0)
      << Log();
  const io::SequenceReader reader = io::SequenceReader::Open(out);
  EXPECT_EQ(reader.meta().model.rings, 32);
  EXPECT_EQ(reader.meta().model.columns, 256);
  EXPECT_NEAR(reader.meta().model.vertical_angles_deg.front(), 10.0, 1e-9);
  EXPECT_NEAR(reader.meta().model.vertical_angles_deg.back(), -20.0, 1e-9);
  const Scan scan = reader.ReadScan(1);
  ASSERT_FALSE(scan.empty());
  for (const auto ring : scan.rings) ASSERT_LT(ring, 32);
}

TEST_F(SimulateCli, BadArgumentsFailWithAMessage) {
  EXPECT_NE(Run("--scene nowhere --scans 2 --out " + (dir_ / "a").string()), 0);
  EXPECT_NE(Log().find("nowhere"), std::string::npos) << Log();
  EXPECT_NE(Run("--scene corridor --scans 2 --vertical-angles 1,5,-3 --out " + (dir_ / "b").string()), 0);
  EXPECT_NE(Log().find("decrease"), std::string::npos) << Log();
  EXPECT_NE(Run("--scene corridor --scans 0 --out " + (dir_ / "c").string()), 0);
}

}  // namespace
}  // namespace dammloam::sim
