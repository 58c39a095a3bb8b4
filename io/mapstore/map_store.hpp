#pragma once
#include <filesystem>

#include "core/backend/keyframe.hpp"
#include "io/io_error.hpp"

// A map directory:
//   map.json         format name, version, counts, Scan Context config, checksum of keyframes.bin
//   keyframes.bin    keyframes (poses, covariances, clouds, labels, descriptors) and loop edges
//   global_map.pcd   the global labelled map (dammloam_pcd layout)
namespace dammloam::mapstore {

inline constexpr int kMapVersion = 1;

// Writes into a temporary sibling directory and renames it into place, so a failed save leaves
// any existing map untouched. An existing `dir` is replaced only if it is a map directory
// (has map.json); anything else there is an error. Throws io::IoError naming the problem.
void SaveMap(const std::filesystem::path& dir, const backend::MapData& map);

// Throws io::IoError naming the file and what is wrong (missing, other version, truncated,
// checksum mismatch, inconsistent counts).
backend::MapData LoadMap(const std::filesystem::path& dir);

}  // namespace dammloam::mapstore
