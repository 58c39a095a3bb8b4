// The map store loader (mapstore::LoadMap: map.json, keyframes.bin, global_map.pcd), as
// dammloamd's relocalize command and dammloam-odometry --localize load a map directory.
//
// Input: u8 flags, u32 length + map.json, u32 length + global_map.pcd, the rest keyframes.bin.
//   flags: bit 0 rewrite map.json's keyframes_bytes and keyframes_fnv1a to match keyframes.bin
//   (when map.json is a JSON object), so that the keyframe decoder is reached past the checksum;
//   bit 1 leave global_map.pcd out; bit 2 leave keyframes.bin out; bit 3 leave map.json out.
// The files are written into a scratch map directory and loaded. Every problem must be an
// io::IoError naming the file.
#include <nlohmann/json.hpp>

#include <cstdint>

#include "io/mapstore/binary_io.hpp"
#include "io/mapstore/map_store.hpp"
#include "io/pcd/labelled_pcd.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::fuzz;

std::string_view AsText(std::span<const std::uint8_t> b) {
  return {reinterpret_cast<const char*>(b.data()), b.size()};
}

void Run(Input& in) {
  const auto flags = in.Get<std::uint8_t>();
  const auto json = in.Bytes(in.Get<std::uint32_t>());
  const auto pcd = in.Bytes(in.Get<std::uint32_t>());
  const auto keyframes = in.Rest();

  static const fs::path dir = ScratchDir() / "map";
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  if ((flags & 8) == 0) {
    std::string text(AsText(json));
    if ((flags & 1) != 0) {
      nlohmann::json meta = nlohmann::json::parse(text, nullptr, false);
      if (!meta.is_discarded() && meta.is_object()) {
        const std::vector<std::uint8_t> kf(keyframes.begin(), keyframes.end());
        meta["keyframes_bytes"] = kf.size();
        meta["keyframes_fnv1a"] = mapstore::Fnv1a64(kf);
        text = meta.dump();
      }
    }
    WriteFile(dir / "map.json", text);
  }
  if ((flags & 2) == 0) WriteFile(dir / "global_map.pcd", pcd);
  if ((flags & 4) == 0) WriteFile(dir / "keyframes.bin", keyframes);

  try {
    const backend::MapData map = mapstore::LoadMap(dir);
    if (map.global_labels.size() != map.global_points.size()) Finding("LoadMap: global labels and points differ in count");
    for (std::size_t i = 0; i < map.keyframes.size(); ++i) {
      const auto& kf = map.keyframes[i];
      if (kf.id != i) Finding("LoadMap: keyframe ids are not dense");
      if (!kf.labels.empty() && kf.labels.size() != kf.points.size()) Finding("LoadMap: keyframe labels and points differ in count");
    }
    for (const auto& loop : map.loops) {
      if (loop.from >= map.keyframes.size() || loop.to >= map.keyframes.size()) Finding("LoadMap: loop to a missing keyframe");
    }
  } catch (const io::IoError& e) {
    // documented; the message names the map directory or one of its files
    if (std::string_view(e.what()).find(dir.string()) == std::string_view::npos) {
      Finding(std::string("LoadMap error does not name the file: ") + e.what());
    }
  }
}

// --- seeds --------------------------------------------------------------------------------

backend::MapData SmallMap(int keyframes, int points, bool labels, bool descriptors) {
  backend::MapData map;
  map.scan_context = {4, 8, 30.0, 1.5};
  for (int k = 0; k < keyframes; ++k) {
    backend::Keyframe kf;
    kf.id = static_cast<std::uint32_t>(k);
    kf.scan_index = static_cast<std::uint64_t>(10 * k);
    kf.stamp = 100.0 + k;
    kf.T_world_sensor_odom.translation() = Eigen::Vector3d(k, 0.5 * k, 0.0);
    kf.T_world_sensor = kf.T_world_sensor_odom;
    for (int i = 0; i < points; ++i) {
      kf.points.emplace_back(i, -i, 0.25 * i);
      if (labels) kf.labels.push_back(static_cast<PointClass>(i % kNumPointClasses));
    }
    if (descriptors) {
      kf.descriptor.grid = Eigen::MatrixXf::Constant(4, 8, 0.5f + k);
      kf.descriptor.ring_key = Eigen::VectorXf::Constant(4, 0.5f + k);
    }
    map.keyframes.push_back(kf);
  }
  if (keyframes >= 2) map.loops.push_back({0, static_cast<std::uint32_t>(keyframes - 1), Eigen::Isometry3d::Identity()});
  for (int i = 0; i < points * keyframes; ++i) {
    map.global_points.emplace_back(0.1 * i, 2.0, -1.0);
    if (labels) map.global_labels.push_back(static_cast<PointClass>(i % kNumPointClasses));
  }
  return map;
}

std::vector<std::uint8_t> Pack(const fs::path& map_dir, std::uint8_t flags, const std::vector<std::uint8_t>* pcd = nullptr) {
  const auto json = ReadFile(map_dir / "map.json");
  const auto cloud = pcd != nullptr ? *pcd : ReadFile(map_dir / "global_map.pcd");
  Bytes b;
  b.Put(flags).Put(static_cast<std::uint32_t>(json.size())).Append(json);
  b.Put(static_cast<std::uint32_t>(cloud.size())).Append(cloud).Append(ReadFile(map_dir / "keyframes.bin"));
  return b.data;
}

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>&) {
  // Maps written by the project's own SaveMap, and their global map in each PCD encoding.
  const fs::path scratch = ScratchDir() / "seed-map";
  int n = 0;
  for (const auto& [keyframes, points, labels, descriptors] :
       {std::tuple{0, 0, false, false}, std::tuple{1, 3, true, true}, std::tuple{3, 6, true, true},
        std::tuple{2, 4, false, false}}) {
    mapstore::SaveMap(scratch, SmallMap(keyframes, points, labels, descriptors));
    WriteSeed(dir, "map-" + std::to_string(n++), Pack(scratch, 0));
    WriteSeed(dir, "map-" + std::to_string(n++), Pack(scratch, 1));
    io::LabelledCloud cloud = io::ReadLabelledPcd(scratch / "global_map.pcd");
    for (auto encoding : {io::PcdEncoding::kAscii, io::PcdEncoding::kBinaryCompressed}) {
      io::WriteLabelledPcd(ScratchDir() / "seed.pcd", cloud, encoding);
      const auto pcd = ReadFile(ScratchDir() / "seed.pcd");
      WriteSeed(dir, "map-" + std::to_string(n++), Pack(scratch, 1, &pcd));
    }
  }
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
