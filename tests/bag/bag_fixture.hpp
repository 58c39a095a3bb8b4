#pragma once
// Shared by the bag tests: small sequences made in the test, and the independent writers and
// readers (tests/bag/node: @mcap/core under node; write_rosbag2_sqlite.py: Python's sqlite3).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/cloud/point_cloud2.hpp"
#include "core/geometry/scan.hpp"
#include "io/sequence_io.hpp"
#include "tests/support/run_command.hpp"

namespace dammloam::test {

inline std::filesystem::path BagTestDir() {
  return std::filesystem::path(DAMMLOAM_SOURCE_DIR) / "tests" / "bag";
}

// Empty when node and the npm packages are there, else why not (for GTEST_SKIP).
inline std::string NodeMissing() {
  if (RunCommand("node --version >/dev/null 2>&1").exit_code != 0) {
    return "node not installed (bash deploy/install-deps.sh)";
  }
  if (!std::filesystem::exists(BagTestDir() / "node" / "node_modules" / "@mcap" / "core")) {
    return "npm packages missing: run npm ci --prefix tests/bag/node (deploy/install-deps.sh "
           "does)";
  }
  return "";
}

#define DAMMLOAM_REQUIRE_NODE()                                          \
  do {                                                                   \
    if (const std::string why = ::dammloam::test::NodeMissing(); !why.empty()) { \
      GTEST_SKIP() << why;                                               \
    }                                                                    \
  } while (0)

// Runs a node script of tests/bag/node with one JSON argument; fails the test on error.
inline std::string RunNode(const std::string& script, const std::string& json) {
  std::string quoted = "'";
  for (char c : json) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  quoted += "'";
  const CommandResult r =
      RunCommand("node " + (BagTestDir() / "node" / script).string() + " " + quoted + " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << script << " " << json << ":\n" << r.output;
  return r.output;
}

// Scans with every field set and easy to check: `count` scans of `points` points, stamps
// 100.1, 100.2, ... (whole nanoseconds, so a bag stamp and times.txt name the same time).
inline std::vector<Scan> TestScans(int count, int points) {
  std::vector<Scan> scans;
  for (int s = 0; s < count; ++s) {
    Scan scan;
    scan.t_start = StampSeconds({100 + (s + 1) / 10, static_cast<std::uint32_t>((s + 1) % 10) * 100000000u});
    for (int i = 0; i < points; ++i) {
      const double a = 0.05 * i + 0.3 * s;
      scan.points.emplace_back(static_cast<float>(5.0 * std::cos(a)),
                               static_cast<float>(5.0 * std::sin(a) + s),
                               static_cast<float>(0.01 * (i % 16) - 0.5));
      scan.intensities.push_back(static_cast<float>((i * 7) % 200));
      scan.times.push_back(static_cast<float>(0.09 * i / points));
      scan.rings.push_back(static_cast<std::int16_t>(i % 16));
    }
    scans.push_back(std::move(scan));
  }
  return scans;
}

inline io::SequenceMeta TestMeta() {
  SensorModel model;
  model.rings = 16;
  model.columns = 100;
  model.scan_period = 0.1;
  return {"test-16", model, io::PointLayout::kXYZITR};
}

inline void WriteSequence(const std::filesystem::path& dir, const std::vector<Scan>& scans,
                          const io::SequenceMeta& meta = TestMeta()) {
  io::SequenceWriter writer(dir, meta);
  for (const Scan& scan : scans) writer.Write(scan);
}

}  // namespace dammloam::test
