// Two consecutive real Velodyne HDL-32E scans (fast_gicp's data): the pipeline's relative pose
// must agree with the published GICP estimate (relative.txt) within a few cm and 0.5 deg.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/odometry/pipeline.hpp"
#include "tests/support/data_dir.hpp"

namespace dammloam {
namespace {

// Minimal reader for the PCD layout these two files have (binary, x y z intensity float32);
// anything else fails the test with the reason.
Scan ReadBinaryXyziPcd(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  EXPECT_TRUE(in) << file;
  std::string line;
  std::size_t points = 0;
  while (std::getline(in, line)) {
    if (line.rfind("FIELDS", 0) == 0) {
      EXPECT_EQ(line, "FIELDS x y z intensity") << file;
    }
    if (line.rfind("POINTS", 0) == 0) points = std::stoul(line.substr(7));
    if (line.rfind("DATA", 0) == 0) {
      EXPECT_EQ(line, "DATA binary") << file;
      break;
    }
  }
  std::vector<float> raw(points * 4);
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size() * 4));
  EXPECT_EQ(static_cast<std::size_t>(in.gcount()), raw.size() * 4) << file;
  Scan scan;
  for (std::size_t i = 0; i < points; ++i) {
    const Eigen::Vector3d p(raw[4 * i], raw[4 * i + 1], raw[4 * i + 2]);
    if (p.isZero()) continue;  // invalid returns stored at the origin (README)
    scan.points.push_back(p);
    scan.intensities.push_back(raw[4 * i + 3]);
  }
  return scan;
}

Eigen::Isometry3d ReadMatrix(const std::filesystem::path& file) {
  std::ifstream in(file);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) in >> m(r, c);
  }
  EXPECT_TRUE(in) << file;
  Eigen::Isometry3d T;
  T.matrix() = m;
  return T;
}

TEST(OdometryRealPair, Hdl32ePairMatchesGicp) {
  const auto dir = test::DataDir() / "hdl32_pair_fast_gicp";
  DAMMLOAM_REQUIRE_DATA(dir / "relative.txt");
  Scan target = ReadBinaryXyziPcd(dir / "251370668.pcd");
  Scan source = ReadBinaryXyziPcd(dir / "251371071.pcd");
  ASSERT_GT(target.size(), 60000u);
  target.t_start = 0.0;
  source.t_start = 0.1;

  SensorModel hdl32;  // HDL-32E: 32 rings from +10.67 to -30.67 deg, ~2170 columns at 10 Hz
  hdl32.rings = 32;
  hdl32.columns = 2170;
  for (int r = 0; r < 32; ++r) hdl32.vertical_angles_deg.push_back(10.67 - r * (41.34 / 31.0));
  hdl32.max_range = 120.0;

  OdometryPipeline pipeline(OdometryConfig{}, hdl32);
  ASSERT_EQ(pipeline.Process(std::move(target)).status, OdometryStatus::kFirstScan);
  const OdometryResult r = pipeline.Process(std::move(source));
  ASSERT_TRUE(Registered(r.status));

  const Eigen::Isometry3d expected = ReadMatrix(dir / "relative.txt");  // T_target_source
  const Vector6d error = LogSE3(expected.inverse() * r.T_world_sensor);
  EXPECT_LT(error.head<3>().norm(), 0.05) << "t = " << r.T_world_sensor.translation().transpose();
  EXPECT_LT(error.tail<3>().norm(), 0.6 * M_PI / 180.0);
}

}  // namespace
}  // namespace dammloam
