#include "io/mapstore/map_store.hpp"

#include <fstream>
#include <type_traits>
#include <utility>
#include <nlohmann/json.hpp>

#include "io/mapstore/binary_io.hpp"
#include "io/mapstore/durable_dir.hpp"
#include "io/pcd/labelled_pcd.hpp"

namespace dammloam::mapstore {

namespace fs = std::filesystem;
using backend::Keyframe;
using backend::LoopConstraint;
using backend::MapData;
using nlohmann::json;

namespace {

constexpr char kFormatName[] = "dammloam-map";
constexpr std::uint32_t kKeyframeMagic = 0x464b4d44;  // "DMKF"
constexpr std::uint32_t kEndMagic = 0x21444e45;       // "END!"

// --- poses and matrices -----------------------------------------------------------------------

void PutPose(ByteWriter& w, const Eigen::Isometry3d& T) {
  const Eigen::Matrix<double, 3, 4> m = T.matrix().topRows<3>();
  w.PutArray(m.data(), 12);
}

Eigen::Isometry3d GetPose(ByteReader& r, const char* what) {
  Eigen::Matrix<double, 3, 4> m;
  r.GetArray(m.data(), 12, what);
  if (!m.allFinite()) throw io::IoError(r.file() + ": non-finite " + what);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix().topRows<3>() = m;
  return Normalized(T);
}

// Rejects counts that cannot fit in the rest of the file before allocating for them.
std::uint32_t GetCount(ByteReader& r, std::size_t element_bytes, const char* what) {
  const auto count = r.Get<std::uint32_t>(what);
  if (element_bytes > 0 && count > r.remaining() / element_bytes) {
    throw io::IoError(r.file() + ": " + what + " " + std::to_string(count) +
                      " exceeds the file size (truncated or corrupt) at byte " +
                      std::to_string(r.offset()));
  }
  return count;
}

// --- keyframes.bin ----------------------------------------------------------------------------

void PutKeyframe(ByteWriter& w, const Keyframe& kf) {
  w.Put(kf.id);
  w.Put(kf.scan_index);
  w.Put(kf.stamp);
  PutPose(w, kf.T_world_sensor_odom);
  PutPose(w, kf.T_world_sensor);
  w.PutArray(kf.edge_covariance.data(), 36);
  w.Put(static_cast<std::uint32_t>(kf.points.size()));
  for (const Eigen::Vector3d& p : kf.points) {
    const Eigen::Vector3f f = p.cast<float>();
    w.PutArray(f.data(), 3);
  }
  w.Put(static_cast<std::uint32_t>(kf.labels.size()));
  for (PointClass c : kf.labels) w.Put(static_cast<std::uint8_t>(c));
  w.Put(static_cast<std::uint32_t>(kf.descriptor.grid.rows()));
  w.Put(static_cast<std::uint32_t>(kf.descriptor.grid.cols()));
  w.PutArray(kf.descriptor.grid.data(), static_cast<std::size_t>(kf.descriptor.grid.size()));
  w.PutArray(kf.descriptor.ring_key.data(), static_cast<std::size_t>(kf.descriptor.ring_key.size()));
}

Keyframe GetKeyframe(ByteReader& r, std::size_t expected_id) {
  Keyframe kf;
  kf.id = r.Get<std::uint32_t>("keyframe id");
  if (kf.id != expected_id) {
    throw io::IoError(r.file() + ": keyframe " + std::to_string(expected_id) + " has id " +
                      std::to_string(kf.id) + " (corrupt)");
  }
  kf.scan_index = r.Get<std::uint64_t>("scan index");
  kf.stamp = r.Get<double>("stamp");
  kf.T_world_sensor_odom = GetPose(r, "odometry pose");
  kf.T_world_sensor = GetPose(r, "corrected pose");
  r.GetArray(kf.edge_covariance.data(), 36, "edge covariance");
  const std::uint32_t num_points = GetCount(r, 3 * sizeof(float), "point count");
  kf.points.resize(num_points);
  for (Eigen::Vector3d& p : kf.points) {
    Eigen::Vector3f f;
    r.GetArray(f.data(), 3, "points");
    p = f.cast<double>();
  }
  const std::uint32_t num_labels = GetCount(r, 1, "label count");
  if (num_labels != 0 && num_labels != num_points) {
    throw io::IoError(r.file() + ": keyframe " + std::to_string(kf.id) + " has " +
                      std::to_string(num_labels) + " labels for " + std::to_string(num_points) +
                      " points");
  }
  kf.labels.resize(num_labels);
  for (PointClass& c : kf.labels) {
    const auto value = r.Get<std::uint8_t>("labels");
    if (value >= kNumPointClasses) {
      throw io::IoError(r.file() + ": keyframe " + std::to_string(kf.id) + " has label " +
                        std::to_string(value) + " outside the five classes");
    }
    c = static_cast<PointClass>(value);
  }
  const auto rings = r.Get<std::uint32_t>("descriptor rings");
  const auto sectors = r.Get<std::uint32_t>("descriptor sectors");
  if (rings > 1024 || sectors > 4096) {
    throw io::IoError(r.file() + ": keyframe " + std::to_string(kf.id) +
                      " has an implausible descriptor size (corrupt)");
  }
  kf.descriptor.grid.resize(rings, sectors);
  r.GetArray(kf.descriptor.grid.data(), std::size_t{rings} * sectors, "descriptor");
  kf.descriptor.ring_key.resize(rings);
  r.GetArray(kf.descriptor.ring_key.data(), rings, "ring key");
  return kf;
}

std::vector<std::uint8_t> EncodeKeyframes(const MapData& map) {
  ByteWriter w;
  w.Put(kKeyframeMagic);
  w.Put(static_cast<std::uint32_t>(kMapVersion));
  w.Put(static_cast<std::uint32_t>(map.keyframes.size()));
  for (const Keyframe& kf : map.keyframes) PutKeyframe(w, kf);
  w.Put(static_cast<std::uint32_t>(map.loops.size()));
  for (const LoopConstraint& loop : map.loops) {
    w.Put(loop.from);
    w.Put(loop.to);
    PutPose(w, loop.T_from_to);
  }
  w.Put(kEndMagic);
  return w.data();
}

void DecodeKeyframes(const std::vector<std::uint8_t>& bytes, const std::string& file,
                     MapData& map) {
  ByteReader r(bytes, file);
  if (r.Get<std::uint32_t>("magic") != kKeyframeMagic) {
    throw io::IoError(file + ": not a dammloam keyframe file (bad magic)");
  }
  const auto version = r.Get<std::uint32_t>("version");
  if (version != static_cast<std::uint32_t>(kMapVersion)) {
    throw io::IoError(file + ": map version " + std::to_string(version) +
                      ", this build reads version " + std::to_string(kMapVersion));
  }
  const std::uint32_t num_keyframes = GetCount(r, 1, "keyframe count");
  map.keyframes.reserve(num_keyframes);
  for (std::uint32_t i = 0; i < num_keyframes; ++i) map.keyframes.push_back(GetKeyframe(r, i));
  const std::uint32_t num_loops = GetCount(r, 8 + 12 * sizeof(double), "loop count");
  for (std::uint32_t i = 0; i < num_loops; ++i) {
    LoopConstraint loop;
    loop.from = r.Get<std::uint32_t>("loop from");
    loop.to = r.Get<std::uint32_t>("loop to");
    loop.T_from_to = GetPose(r, "loop pose");
    if (loop.from >= num_keyframes || loop.to >= num_keyframes) {
      throw io::IoError(file + ": loop " + std::to_string(i) + " refers to a missing keyframe");
    }
    map.loops.push_back(loop);
  }
  if (r.Get<std::uint32_t>("end marker") != kEndMagic || r.remaining() != 0) {
    throw io::IoError(file + ": bad end marker or trailing bytes (corrupt)");
  }
}

// --- files ------------------------------------------------------------------------------------

std::vector<std::uint8_t> ReadFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw io::IoError(file.string() + ": missing or unreadable");
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

json ScanContextToJson(const backend::ScanContextConfig& c) {
  return {{"rings", c.rings}, {"sectors", c.sectors}, {"max_range", c.max_range},
          {"sensor_height", c.sensor_height}};
}

// Every file is on disk (fsync) when this returns; map.json, which the loader checks the others
// against, is written last.
void WriteMapInto(const fs::path& dir, const MapData& map) {
  const std::vector<std::uint8_t> keyframes = EncodeKeyframes(map);
  WriteFileDurably(dir / "keyframes.bin", keyframes.data(), keyframes.size());

  if (!map.global_labels.empty() && map.global_labels.size() != map.global_points.size()) {
    throw io::IoError(dir.string() + ": global map has " + std::to_string(map.global_labels.size()) +
                      " labels for " + std::to_string(map.global_points.size()) + " points");
  }
  io::LabelledCloud cloud;
  cloud.points = map.global_points;
  cloud.labels = map.global_labels;
  io::WriteLabelledPcd(dir / "global_map.pcd", cloud);
  SyncPath(dir / "global_map.pcd");

  const json meta = {{"format", kFormatName},
                     {"version", kMapVersion},
                     {"num_keyframes", map.keyframes.size()},
                     {"num_loops", map.loops.size()},
                     {"num_global_points", map.global_points.size()},
                     {"scan_context", ScanContextToJson(map.scan_context)},
                     {"keyframes_bytes", keyframes.size()},
                     {"keyframes_fnv1a", Fnv1a64(keyframes)}};
  const std::string text = meta.dump(2) + "\n";
  WriteFileDurably(dir / "map.json", text.data(), text.size());
}

// Absolute, without a trailing slash: the staging directory is a sibling named after it.
fs::path TargetPath(const fs::path& dir) {
  fs::path target = fs::absolute(dir).lexically_normal();
  if (target.filename().empty()) target = target.parent_path();
  return target;
}

// An existing `dir` is replaced only if it is a map directory (or empty): never a user's folder.
void CheckReplaceable(const fs::path& dir) {
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status)) return;
  const bool is_map = fs::is_directory(status) &&
                      (fs::exists(dir / "map.json", ec) || fs::is_empty(dir, ec));
  if (!is_map) {
    throw io::IoError(dir.string() + ": exists and is not a map directory; refusing to replace it");
  }
}

template <typename T>
T Field(const json& meta, const char* name, const fs::path& file) {
  if (!meta.contains(name)) throw io::IoError(file.string() + ": missing field '" + name + "'");
  if constexpr (std::is_integral_v<T>) {
    // get<int>() casts whatever number is there: undefined for 1e300, wrapped for 2^32 + 1.
    const json& value = meta.at(name);
    const bool fits = value.is_number_unsigned() ? std::in_range<T>(value.get<std::uint64_t>())
                      : value.is_number_integer() && std::in_range<T>(value.get<std::int64_t>());
    if (!fits) {
      throw io::IoError(file.string() + ": field '" + name + "' is not an integer in range");
    }
  }
  try {
    return meta.at(name).get<T>();
  } catch (const json::exception&) {
    throw io::IoError(file.string() + ": field '" + name + "' has the wrong type");
  }
}

}  // namespace

void SaveMap(const fs::path& dir_in, const MapData& map) {
  const fs::path dir = TargetPath(dir_in);
  CheckReplaceable(dir);
  CreateParentsDurably(dir);
  RemoveInterruptedSaves(dir);
  const fs::path staging = MakeStagingSibling(dir);
  try {
    WriteMapInto(staging, map);
    SyncPath(staging);
    PublishStaging(staging, dir);
  } catch (...) {
    // `staging` holds the unfinished new map, or the old one if only the final parent sync
    // failed: either way `dir` holds a complete map.
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
  // The previous map now sits under the staging name. The save has succeeded, so a failure to
  // delete it is not reported: a later load or save in another process removes the left-over.
  std::error_code ignored;
  fs::remove_all(staging, ignored);
}

MapData LoadMap(const fs::path& dir) {
  std::error_code ec;
  // `dir` itself is always a complete map; only siblings of killed saves are removed.
  RemoveInterruptedSaves(TargetPath(dir));
  if (!fs::is_directory(dir, ec)) throw io::IoError(dir.string() + ": not a directory");
  const fs::path meta_file = dir / "map.json";
  const std::vector<std::uint8_t> meta_bytes = ReadFile(meta_file);
  const json meta = json::parse(meta_bytes.begin(), meta_bytes.end(), nullptr, false);
  if (meta.is_discarded() || !meta.is_object()) {
    throw io::IoError(meta_file.string() + ": not valid JSON (corrupt or truncated)");
  }
  if (Field<std::string>(meta, "format", meta_file) != kFormatName) {
    throw io::IoError(meta_file.string() + ": format is not '" + kFormatName + "'");
  }
  const int version = Field<int>(meta, "version", meta_file);
  if (version != kMapVersion) {
    throw io::IoError(meta_file.string() + ": map version " + std::to_string(version) +
                      ", this build reads version " + std::to_string(kMapVersion));
  }
  MapData map;
  const json sc = Field<json>(meta, "scan_context", meta_file);
  map.scan_context.rings = Field<int>(sc, "rings", meta_file);
  map.scan_context.sectors = Field<int>(sc, "sectors", meta_file);
  map.scan_context.max_range = Field<double>(sc, "max_range", meta_file);
  map.scan_context.sensor_height = Field<double>(sc, "sensor_height", meta_file);

  const fs::path kf_file = dir / "keyframes.bin";
  const std::vector<std::uint8_t> keyframes = ReadFile(kf_file);
  if (keyframes.size() != Field<std::size_t>(meta, "keyframes_bytes", meta_file)) {
    throw io::IoError(kf_file.string() + ": size " + std::to_string(keyframes.size()) +
                      " bytes differs from map.json (truncated)");
  }
  if (Fnv1a64(keyframes) != Field<std::uint64_t>(meta, "keyframes_fnv1a", meta_file)) {
    throw io::IoError(kf_file.string() + ": checksum mismatch (corrupt)");
  }
  DecodeKeyframes(keyframes, kf_file.string(), map);
  if (map.keyframes.size() != Field<std::size_t>(meta, "num_keyframes", meta_file)) {
    throw io::IoError(kf_file.string() + ": keyframe count differs from map.json");
  }
  for (const Keyframe& kf : map.keyframes) {
    const bool size_ok = kf.descriptor.grid.rows() == map.scan_context.rings &&
                         kf.descriptor.grid.cols() == map.scan_context.sectors;
    if (!kf.descriptor.empty() && !size_ok) {
      throw io::IoError(kf_file.string() + ": keyframe " + std::to_string(kf.id) +
                        " descriptor size differs from map.json's scan_context");
    }
  }

  io::LabelledCloud cloud = io::ReadLabelledPcd(dir / "global_map.pcd");
  if (cloud.size() != Field<std::size_t>(meta, "num_global_points", meta_file)) {
    throw io::IoError((dir / "global_map.pcd").string() + ": point count differs from map.json");
  }
  map.global_points = std::move(cloud.points);
  map.global_labels = cloud.labels.empty()
                          ? std::vector<PointClass>(map.global_points.size(), PointClass::Unknown)
                          : std::move(cloud.labels);
  return map;
}

}  // namespace dammloam::mapstore
