#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dammloam::io {

// Decompresses an MCAP chunk or a compressed rosbag2 message: compression "" (stored),
// "zstd" (a zstd frame) or "lz4" (an LZ4 frame). The result must be exactly
// `uncompressed_size` bytes. Throws IoError "<where>: ..." for an unknown compression or
// corrupt data. `out` is reused between calls so a chunk stream allocates once.
void Decompress(std::string_view compression, const std::uint8_t* data, std::size_t size,
                std::uint64_t uncompressed_size, std::vector<std::uint8_t>& out,
                const std::string& where);

// One zstd frame whose header states its decompressed size (rosbag2 per-message compression),
// at most max_bytes. Throws IoError "<where>: ..." otherwise.
void DecompressZstdFrame(const std::uint8_t* data, std::size_t size, std::uint64_t max_bytes,
                         std::vector<std::uint8_t>& out, const std::string& where);

// A bzip2 stream (ROS 1 bag chunks) of exactly `uncompressed_size` bytes. Throws IoError
// "<where>: ..." for corrupt data or another size.
void DecompressBz2(const std::uint8_t* data, std::size_t size, std::uint64_t uncompressed_size,
                   std::vector<std::uint8_t>& out, const std::string& where);

// zstd frame compression (MCAP out).
std::vector<std::uint8_t> CompressZstd(const std::uint8_t* data, std::size_t size, int level);

// CRC-32 (ISO-HDLC, as zlib and MCAP use), continuing from `crc` (0 to start).
std::uint32_t Crc32(std::uint32_t crc, const std::uint8_t* data, std::size_t size);

}  // namespace dammloam::io
