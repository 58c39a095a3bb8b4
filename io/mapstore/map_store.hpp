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

// Crash-safe: writes into a sibling "<dir>.tmp-<pid>-XXXXXX", fsyncs every file and that
// directory, swaps it with `dir` in one atomic renameat2(RENAME_EXCHANGE) (RENAME_NOREPLACE for
// a first save), fsyncs the parent, then deletes the old map. At every instant, including after
// a SIGKILL or a power cut, `dir` holds either the complete old or the complete new map; the
// layout inside `dir` is unchanged. An existing `dir` is replaced only if it is a map directory
// (has map.json) or empty; anything else there is an error. Needs a file system with
// RENAME_EXCHANGE (ext4, xfs, btrfs, tmpfs, overlayfs); elsewhere the save fails, the old map
// untouched. Throws io::IoError naming the path and the errno text (disk full, permission).
void SaveMap(const std::filesystem::path& dir, const backend::MapData& map);

// First removes the staging left-overs of saves whose process is gone (never `dir` itself).
// Throws io::IoError naming the file and what is wrong (missing, other version, truncated,
// checksum mismatch, inconsistent counts).
backend::MapData LoadMap(const std::filesystem::path& dir);

}  // namespace dammloam::mapstore
