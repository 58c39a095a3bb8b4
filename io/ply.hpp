#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/geometry/scan.hpp"

namespace dammloam::io {

struct PlyReadReport {
  std::size_t dropped = 0;  // vertices with a non-finite coordinate or exactly at the origin
};

// A point cloud in PLY (format ascii 1.0 or binary_little_endian 1.0): the `vertex` element's x y z
// (any numeric type), and when present `intensity`, per-point time `t` or `time` (float: seconds;
// integer: nanoseconds; times are made relative to the earliest one when they do not already lie
// in [0, 1) s) and `ring`. Elements before `vertex` are skipped (list properties only after it);
// elements after it are ignored. Vertices with a non-finite coordinate or exactly at (0,0,0)
// (invalid returns) are dropped and counted. t_start is left 0 for the caller. Throws IoError
// "<name>: ..." naming the header line, or the vertex and byte offset, of any problem.
Scan ParsePly(const std::uint8_t* data, std::size_t size, const std::string& name,
              PlyReadReport* report = nullptr);
Scan ReadPly(const std::filesystem::path& file, PlyReadReport* report = nullptr);

}  // namespace dammloam::io
