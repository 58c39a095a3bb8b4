#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "core/backend/scan_context.hpp"
#include "io/mapstore/map_store.hpp"
#include "tests/support/temp_dir.hpp"

namespace dammloam::mapstore {
namespace {

namespace fs = std::filesystem;

backend::MapData SmallMap() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  backend::MapData map;
  for (std::uint32_t k = 0; k < 3; ++k) {
    backend::Keyframe kf;
    kf.id = k;
    kf.scan_index = 10 * k;
    kf.stamp = 100.0 + k;
    kf.T_world_sensor_odom.translation() << k, 0.5 * k, 0;
    kf.T_world_sensor = kf.T_world_sensor_odom;
    kf.T_world_sensor.linear() = Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    for (int i = 0; i < 200; ++i) {
      kf.points.emplace_back(u(rng), u(rng), u(rng) * 0.1);
      kf.labels.push_back(static_cast<PointClass>(i % 5));
    }
    kf.descriptor = backend::MakeScanContext(kf.points, map.scan_context);
    map.keyframes.push_back(kf);
  }
  map.loops.push_back({0, 2, map.keyframes[2].T_world_sensor});
  for (int i = 0; i < 500; ++i) {
    map.global_points.emplace_back(u(rng), u(rng), u(rng));
    map.global_labels.push_back(static_cast<PointClass>(i % 5));
  }
  return map;
}

std::string LoadError(const fs::path& dir) {
  try {
    LoadMap(dir);
  } catch (const io::IoError& e) {
    return e.what();
  }
  return "";
}

TEST(MapStore, RoundTrip) {
  const test::TempDir tmp;
  const backend::MapData map = SmallMap();
  SaveMap(tmp / "map", map);
  const backend::MapData loaded = LoadMap(tmp / "map");
  ASSERT_EQ(loaded.keyframes.size(), map.keyframes.size());
  for (std::size_t k = 0; k < map.keyframes.size(); ++k) {
    const auto& a = map.keyframes[k];
    const auto& b = loaded.keyframes[k];
    EXPECT_EQ(a.scan_index, b.scan_index);
    EXPECT_DOUBLE_EQ(a.stamp, b.stamp);
    EXPECT_TRUE(a.T_world_sensor.isApprox(b.T_world_sensor, 1e-12));
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_LT((a.points[7] - b.points[7]).norm(), 1e-5);  // stored as float
    EXPECT_EQ(a.labels, b.labels);
    EXPECT_TRUE(a.descriptor.grid.isApprox(b.descriptor.grid));
    EXPECT_TRUE(a.descriptor.ring_key.isApprox(b.descriptor.ring_key));
  }
  ASSERT_EQ(loaded.loops.size(), 1u);
  EXPECT_EQ(loaded.loops[0].to, 2u);
  EXPECT_EQ(loaded.global_points.size(), map.global_points.size());
  EXPECT_EQ(loaded.global_labels, map.global_labels);
  EXPECT_EQ(loaded.scan_context.sectors, map.scan_context.sectors);
  // Saving again over an existing map replaces it.
  backend::MapData smaller = map;
  smaller.keyframes.pop_back();
  smaller.loops.clear();
  SaveMap(tmp / "map", smaller);
  EXPECT_EQ(LoadMap(tmp / "map").keyframes.size(), 2u);
  for (const auto& entry : fs::directory_iterator(tmp.path())) {
    EXPECT_EQ(entry.path().filename(), "map") << "left-over staging directory";
  }
}

TEST(MapStore, CorruptTruncatedAndOtherVersionGiveClearErrors) {
  const test::TempDir tmp;
  const fs::path dir = tmp / "map";
  SaveMap(dir, SmallMap());
  const fs::path kf = dir / "keyframes.bin";
  const auto original_size = fs::file_size(kf);

  {  // one flipped byte in the middle
    std::fstream f(kf, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(original_size / 2));
    f.put('\x5a');
  }
  EXPECT_NE(LoadError(dir).find("checksum"), std::string::npos) << LoadError(dir);

  fs::resize_file(kf, original_size / 3);
  EXPECT_NE(LoadError(dir).find("truncated"), std::string::npos) << LoadError(dir);

  SaveMap(dir, SmallMap());
  {
    std::ifstream in(dir / "map.json");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    text.replace(text.find("\"version\": 1"), 12, "\"version\": 7");
    std::ofstream(dir / "map.json") << text;
  }
  EXPECT_NE(LoadError(dir).find("version 7"), std::string::npos) << LoadError(dir);

  SaveMap(dir, SmallMap());
  fs::resize_file(dir / "map.json", 20);
  EXPECT_NE(LoadError(dir).find("map.json"), std::string::npos) << LoadError(dir);

  fs::remove(dir / "map.json");
  EXPECT_NE(LoadError(dir).find("missing"), std::string::npos) << LoadError(dir);
  EXPECT_NE(LoadError(tmp / "nowhere").find("not a directory"), std::string::npos);
}

TEST(MapStore, FailedSaveOverwritesNothing) {
  const test::TempDir tmp;
  const fs::path dir = tmp / "map";
  SaveMap(dir, SmallMap());
  const auto before = fs::file_size(dir / "keyframes.bin");
  backend::MapData bad = SmallMap();
  bad.keyframes.pop_back();
  bad.global_labels.pop_back();  // inconsistent: detected mid-save
  EXPECT_THROW(SaveMap(dir, bad), io::IoError);
  EXPECT_EQ(fs::file_size(dir / "keyframes.bin"), before);
  EXPECT_EQ(LoadMap(dir).keyframes.size(), 3u);

  // A directory that is not a map is never replaced.
  const fs::path other = tmp / "photos";
  fs::create_directories(other);
  std::ofstream(other / "holiday.jpg") << "precious";
  try {
    SaveMap(other, SmallMap());
    FAIL() << "saved over a non-map directory";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("not a map directory"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(other / "holiday.jpg"));
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(tmp.path())) ++entries;
  EXPECT_EQ(entries, 2u);  // map/ and photos/, no staging left-overs
}

}  // namespace
}  // namespace dammloam::mapstore
