#pragma once
#include <cstdint>
#include <vector>

namespace dammloam::drivers::ouster {

// One frame exactly as the packets carried it: "staggered" images, row = beam, column =
// measurement id, row-major (index = beam * cols + column). Fields a profile lacks stay zero.
struct LidarFrame {
  std::uint32_t frame_id = 0;
  int rows = 0;
  int cols = 0;
  std::vector<std::uint32_t> range;         // mm
  std::vector<std::uint32_t> range2;        // mm, dual profiles
  std::vector<std::uint8_t> reflectivity;
  std::vector<std::uint8_t> reflectivity2;
  std::vector<std::uint16_t> signal;
  std::vector<std::uint16_t> signal2;
  std::vector<std::uint16_t> near_ir;
  std::vector<std::uint64_t> timestamp;       // per column, ns
  std::vector<std::uint16_t> measurement_id;  // per column
  std::vector<std::uint64_t> status;          // per column, as the packet carries it
  std::vector<std::uint32_t> encoder_count;   // per column (LEGACY only)
  std::vector<std::uint8_t> column_received;  // per column
  int columns_received = 0;
  bool complete = false;  // every column of the column window arrived

  void Reset(int h, int w) {
    rows = h;
    cols = w;
    const auto n = static_cast<std::size_t>(h) * static_cast<std::size_t>(w);
    const auto c = static_cast<std::size_t>(w);
    range.assign(n, 0);
    range2.assign(n, 0);
    reflectivity.assign(n, 0);
    reflectivity2.assign(n, 0);
    signal.assign(n, 0);
    signal2.assign(n, 0);
    near_ir.assign(n, 0);
    timestamp.assign(c, 0);
    measurement_id.assign(c, 0);
    status.assign(c, 0);
    encoder_count.assign(c, 0);
    column_received.assign(c, 0);
    columns_received = 0;
    complete = false;
  }
};

}  // namespace dammloam::drivers::ouster
