#include "io/bag/decompress.hpp"

#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <limits>
#include <memory>

#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

void Zstd(const std::uint8_t* data, std::size_t size, std::vector<std::uint8_t>& out,
          const std::string& where) {
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), data, size);
  if (ZSTD_isError(n)) {
    throw IoError(where + ": zstd: " + ZSTD_getErrorName(n));
  }
  if (n != out.size()) {
    throw IoError(where + ": zstd gave " + std::to_string(n) + " bytes, the record says " +
                  std::to_string(out.size()));
  }
}

void Lz4(const std::uint8_t* data, std::size_t size, std::vector<std::uint8_t>& out,
         const std::string& where) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) {
    throw IoError(where + ": lz4: cannot create a decompression context");
  }
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> context(
      raw, &LZ4F_freeDecompressionContext);
  std::size_t in_pos = 0, out_pos = 0;
  while (in_pos < size) {
    std::size_t in_n = size - in_pos, out_n = out.size() - out_pos;
    const std::size_t hint = LZ4F_decompress(context.get(), out.data() + out_pos, &out_n,
                                             data + in_pos, &in_n, nullptr);
    if (LZ4F_isError(hint)) throw IoError(where + ": lz4: " + LZ4F_getErrorName(hint));
    in_pos += in_n;
    out_pos += out_n;
    if (hint == 0) break;  // end of frame
    if (in_n == 0 && out_n == 0) {
      throw IoError(where + ": lz4: output larger than the record's uncompressed size " +
                    std::to_string(out.size()));
    }
  }
  if (out_pos != out.size()) {
    throw IoError(where + ": lz4 gave " + std::to_string(out_pos) + " bytes, the record says " +
                  std::to_string(out.size()));
  }
}

}  // namespace

void Decompress(std::string_view compression, const std::uint8_t* data, std::size_t size,
                std::uint64_t uncompressed_size, std::vector<std::uint8_t>& out,
                const std::string& where) {
  if (compression != "" && compression != "zstd" && compression != "lz4") {
    throw IoError(where + ": unknown compression '" + std::string(compression) +
                  "' (supported: none, zstd, lz4)");
  }
  if (compression.empty() && size != uncompressed_size) {
    throw IoError(where + ": uncompressed data of " + std::to_string(size) +
                  " bytes but the record says " + std::to_string(uncompressed_size));
  }
  if (uncompressed_size > std::numeric_limits<std::size_t>::max()) {
    throw IoError(where + ": uncompressed size " + std::to_string(uncompressed_size) + " too large");
  }
  out.resize(static_cast<std::size_t>(uncompressed_size));
  if (compression.empty()) {
    if (size > 0) std::copy(data, data + size, out.begin());
  } else if (compression == "zstd") {
    Zstd(data, size, out, where);
  } else {
    Lz4(data, size, out, where);
  }
}

void DecompressZstdFrame(const std::uint8_t* data, std::size_t size, std::uint64_t max_bytes,
                         std::vector<std::uint8_t>& out, const std::string& where) {
  const unsigned long long n = ZSTD_getFrameContentSize(data, size);
  if (n == ZSTD_CONTENTSIZE_ERROR || n == ZSTD_CONTENTSIZE_UNKNOWN) {
    throw IoError(where + ": not a zstd frame with a known size");
  }
  if (n > max_bytes) {
    throw IoError(where + ": zstd frame of " + std::to_string(n) + " bytes exceeds the limit");
  }
  out.resize(static_cast<std::size_t>(n));
  Zstd(data, size, out, where);
}

void DecompressBz2(const std::uint8_t* data, std::size_t size, std::uint64_t uncompressed_size,
                   std::vector<std::uint8_t>& out, const std::string& where) {
  if (uncompressed_size > std::numeric_limits<unsigned int>::max() ||
      size > std::numeric_limits<unsigned int>::max()) {
    throw IoError(where + ": bz2 data of " + std::to_string(size) + " -> " +
                  std::to_string(uncompressed_size) + " bytes is too large");
  }
  // One spare byte: output that does not fit in the stated size is reported, not truncated.
  out.resize(static_cast<std::size_t>(uncompressed_size) + 1);
  unsigned int n = static_cast<unsigned int>(out.size());
  const int rc = BZ2_bzBuffToBuffDecompress(
      reinterpret_cast<char*>(out.data()), &n,
      const_cast<char*>(reinterpret_cast<const char*>(data)), static_cast<unsigned int>(size), 0, 0);
  if (rc == BZ_OUTBUFF_FULL) {
    throw IoError(where + ": bz2 output larger than the record's uncompressed size " +
                  std::to_string(uncompressed_size));
  }
  if (rc != BZ_OK) throw IoError(where + ": bz2: corrupt data (error " + std::to_string(rc) + ")");
  if (n != uncompressed_size) {
    throw IoError(where + ": bz2 gave " + std::to_string(n) + " bytes, the record says " +
                  std::to_string(uncompressed_size));
  }
  out.resize(n);
}

std::vector<std::uint8_t> CompressZstd(const std::uint8_t* data, std::size_t size, int level) {
  std::vector<std::uint8_t> out(ZSTD_compressBound(size));
  const std::size_t n = ZSTD_compress(out.data(), out.size(), data, size, level);
  if (ZSTD_isError(n)) throw IoError(std::string("zstd compression: ") + ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

std::uint32_t Crc32(std::uint32_t crc, const std::uint8_t* data, std::size_t size) {
  // zlib takes uInt lengths: feed very large buffers in pieces.
  while (size > 0) {
    const uInt n = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    crc = static_cast<std::uint32_t>(crc32(crc, data, n));
    data += n;
    size -= n;
  }
  return crc;
}

}  // namespace dammloam::io
