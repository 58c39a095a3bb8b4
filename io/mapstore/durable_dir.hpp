#pragma once
#include <cstddef>
#include <filesystem>

#include "io/io_error.hpp"

// Crash-safe replacement of a whole directory (POSIX + Linux renameat2). Every failure throws
// io::IoError naming the path and the errno text.
namespace dammloam::mapstore {

// Writes `size` bytes to a new file (truncating any old one) and fsyncs it before returning.
void WriteFileDurably(const std::filesystem::path& file, const void* data, std::size_t size);

// fsync of a file or directory that is already written (a directory fsync makes its entries
// durable: created files, renames).
void SyncPath(const std::filesystem::path& path);

// Creates the missing ancestors of `dir` (not `dir` itself), each made durable in its parent.
void CreateParentsDurably(const std::filesystem::path& dir);

// A new empty sibling of `target` named "<target>.tmp-<pid>-XXXXXX": the pid lets a later load
// tell the left-overs of a killed process from a save still running in another one.
std::filesystem::path MakeStagingSibling(const std::filesystem::path& target);

// Makes the complete, synced directory `staging` visible as `target` in one atomic step
// (renameat2 RENAME_EXCHANGE when `target` exists, RENAME_NOREPLACE otherwise) and syncs the
// parent. On return `target` holds the new contents and `staging` the old ones (or is gone).
void PublishStaging(const std::filesystem::path& staging, const std::filesystem::path& target);

// Best effort (never throws): removes "<target>.tmp-<pid>-*" siblings whose process is gone,
// and "<target>.old-<pid>-*" ones left by the earlier two-rename scheme when `target` exists.
// Returns the number removed.
std::size_t RemoveInterruptedSaves(const std::filesystem::path& target);

}  // namespace dammloam::mapstore
