// The presets without actors must simulate exactly what they did before actors existed: adding
// actors must not shift a single noise draw, carrier sample or point of a static run.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {
namespace {

// FNV-1a over bytes: tiny, stable across platforms and compilers.
struct Fnv1a {
  std::uint64_t state = 0xCBF29CE484222325ull;
  void Add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      state ^= bytes[i];
      state *= 0x100000001B3ull;
    }
  }
  void AddFloat(double value) {
    const float f = static_cast<float>(value);
    Add(&f, sizeof f);
  }
};

// Hashes what a sequence file would hold (float32 x y z intensity t ring per point, the scan's
// start time and the ground-truth pose at it), so one double rounding differently in another
// build type does not change the hash, but any moved, added or lost point does.
std::uint64_t HashOfFirstScans(const std::string& preset, int scans) {
  const Simulator sim(*FindPreset(preset), Vlp16(), 1);
  Fnv1a hash;
  for (int k = 0; k < scans; ++k) {
    const Scan scan = sim.SimulateScan(k);
    hash.Add(&scan.t_start, sizeof scan.t_start);
    const Eigen::Isometry3d T = sim.PoseAt(scan.t_start);
    const Eigen::Quaterniond q(T.linear());
    for (int i = 0; i < 3; ++i) hash.AddFloat(T.translation()[i]);
    for (const double c : {q.x(), q.y(), q.z(), q.w()}) hash.AddFloat(c);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      for (int j = 0; j < 3; ++j) hash.AddFloat(scan.points[i][j]);
      hash.AddFloat(scan.intensities[i]);
      hash.AddFloat(scan.times[i]);
      hash.AddFloat(scan.rings[i]);
    }
  }
  return hash.state;
}

TEST(StaticPresets, FirstScansAreBitIdenticalToBeforeActors) {
  // Recorded before actors were added (vlp-16, seed 1, 30 scans).
  EXPECT_EQ(HashOfFirstScans("handheld-corridor", 30), 0xb407b19daf7ae9ffull);
  EXPECT_EQ(HashOfFirstScans("wheeled-zigzag", 30), 0x81a06a36c456ad17ull);
}

}  // namespace
}  // namespace dammloam::sim
