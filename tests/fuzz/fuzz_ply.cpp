// The PLY reader (io::ParsePly: header, ascii and binary_little_endian vertices, intensity, time
// and ring) as the cloud-folder input reads a .ply file.
//
// Input: the whole file. Only io::IoError may escape; a scan must have parallel vectors and
// only finite points off the origin.
#include <cmath>
#include <cstdint>

#include "io/io_error.hpp"
#include "io/ply.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::fuzz;

void Run(Input& in) {
  const std::span<const std::uint8_t> bytes = in.Rest();
  try {
    io::PlyReadReport report;
    const Scan scan = io::ParsePly(bytes.data(), bytes.size(), "fuzz.ply", &report);
    const std::size_t n = scan.size();
    if (!scan.times.empty() && scan.times.size() != n) Finding("times and points differ in number");
    if (!scan.intensities.empty() && scan.intensities.size() != n) Finding("intensities and points differ in number");
    if (!scan.rings.empty() && scan.rings.size() != n) Finding("rings and points differ in number");
    for (const auto& p : scan.points) {
      if (!p.allFinite() || p.isZero()) Finding("a non-finite point or one at the origin was kept");
    }
  } catch (const io::IoError&) {
    // documented: every problem of the file
  }
}

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>&) {
  const std::string header = "property float x\nproperty float y\nproperty float z\nproperty float intensity\n"
                             "property double t\nproperty ushort ring\n";
  WriteSeed(dir, "ascii",
            Bytes()
                .Append("ply\nformat ascii 1.0\ncomment seed\nelement vertex 3\n" + header +
                        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                        "1 2 3 10 0.01 0\n-1 0.5 2 20 0.02 1\n0 0 0 0 0 2\n3 0 1 2\n")
                .data);
  Bytes binary;
  binary.Append("ply\r\nformat binary_little_endian 1.0\r\nelement camera 1\r\nproperty uchar k\r\nelement vertex 2\r\n" +
                header + "end_header\r\n");
  binary.Put<std::uint8_t>(7);
  for (int i = 0; i < 2; ++i) {
    binary.Put(1.5f + static_cast<float>(i)).Put(-2.0f).Put(0.25f).Put(42.0f).Put(1700000000.0 + 0.05 * i).Put<std::uint16_t>(3);
  }
  WriteSeed(dir, "binary", binary.data);
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
