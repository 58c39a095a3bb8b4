#pragma once
// Shared by the tests of the input kinds of issue 54 (ROS 1 bags, captures, cloud folders).
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/bag/bag_fixture.hpp"
#include "tests/support/data_dir.hpp"

namespace dammloam::test {

namespace fs = std::filesystem;

inline fs::path OusterDir() { return DataDir() / "ouster_sdk_pcaps"; }
inline fs::path RustDir() { return DataDir() / "velodyne_ouster_pcaps_rust_lidar_utils"; }

// Empty when /usr/bin/python3 imports Debian's rosbag, else why not.
inline std::string RosbagMissing() {
  if (RunCommand("/usr/bin/python3 -c 'import rosbag, roslz4, sensor_msgs.msg' >/dev/null 2>&1").exit_code != 0) {
    return "python3-rosbag, python3-roslz4 or python3-sensor-msgs not installed (bash deploy/install-deps.sh)";
  }
  return "";
}

inline void WriteRosbag(const fs::path& seq, const fs::path& bag, const std::string& compression) {
  const auto r = RunCommand("/usr/bin/python3 " + (BagTestDir() / "write_ros1_bag.py").string() + " " +
                                  seq.string() + " " + bag.string() + " " + compression + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace dammloam::test
