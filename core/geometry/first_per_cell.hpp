#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tsl/robin_set.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#include "core/geometry/voxel.hpp"

namespace dammloam {

// The first point of every distinct cell, in input order: what a serial loop "keep the point
// if its cell is new" returns, computed on several cores. Cells are split between tasks by a
// bit of their hash, so each task owns whole cells and sees their points in input order: the
// answer is the serial one whatever the number of threads. The tables are kept between calls
// (they settle at the size a scan needs and stop allocating).
template <typename Cell, typename CellHash>
class FirstPerCell {
 public:
  // cell_of(i) -> Cell for i in [0, n). Returns ascending indices.
  template <typename CellOf>
  std::vector<std::size_t> Select(std::size_t n, CellOf cell_of) {
    cells_.resize(n);
    parts_.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        cells_[i] = cell_of(i);
        parts_[i] = Part(cells_[i]);
      }
    });
    tbb::parallel_for(std::size_t{0}, kParts, [&](std::size_t part) { SelectPart(part); });
    std::vector<std::size_t> kept;
    kept.reserve(kept_[0].size() + kept_[1].size());
    std::merge(kept_[0].begin(), kept_[0].end(), kept_[1].begin(), kept_[1].end(),
               std::back_inserter(kept));
    return kept;
  }

 private:
  static constexpr std::size_t kParts = 2;  // the machines this runs on have 2-8 cores

  // The hash's low bits pick the table bucket, so the split uses a mixed high bit: a table
  // holding only cells with one value of a low bit would use half its buckets.
  static std::uint8_t Part(const Cell& cell) {
    const std::uint64_t mixed = static_cast<std::uint64_t>(CellHash{}(cell)) * 0x9E3779B97F4A7C15ull;
    return static_cast<std::uint8_t>(mixed >> 63);
  }

  void SelectPart(std::size_t part) {
    tsl::robin_set<Cell, CellHash>& seen = seen_[part];
    std::vector<std::size_t>& kept = kept_[part];
    seen.clear();  // keeps its buckets
    kept.clear();
    for (std::size_t i = 0; i < cells_.size(); ++i) {
      if (parts_[i] != part) continue;
      // Consecutive points (one firing) often share a cell: the second cannot be first.
      if (i > 0 && cells_[i] == cells_[i - 1]) continue;
      if (seen.insert(cells_[i]).second) kept.push_back(i);
    }
  }

  std::vector<Cell> cells_;
  std::vector<std::uint8_t> parts_;
  std::array<tsl::robin_set<Cell, CellHash>, kParts> seen_;
  std::array<std::vector<std::size_t>, kParts> kept_;
};

}  // namespace dammloam
