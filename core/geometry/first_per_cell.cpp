#include "core/geometry/first_per_cell.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>

namespace dammloam {
namespace {

// The tables index buckets by the hash's low bits; partitions take the top bits of a mixed
// copy, or each table would fill only a quarter of its buckets.
std::uint8_t PartitionOf(const ClassVoxel& cell) {
  constexpr std::uint64_t kMix = 0x9E3779B97F4A7C15ULL;
  return static_cast<std::uint8_t>((std::uint64_t{ClassVoxelHash{}(cell)} * kMix) >> 62);
}

}  // namespace

std::vector<std::size_t> FirstPerCell::Select(
    const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
    const std::array<double, kNumPointClasses>& voxel_sizes) {
  const std::size_t n = points.size();
  cells_.resize(n);
  partition_.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const PointClass label = i < labels.size() ? labels[i] : PointClass::Unknown;
      const std::size_t c = std::min<std::size_t>(Index(label), kNumPointClasses - 1);
      cells_[i] = {PointToVoxel(points[i], voxel_sizes[c]), label};
      partition_[i] = PartitionOf(cells_[i]);
    }
  });
  kept_.assign(n, 0);
  tbb::parallel_for(std::size_t{0}, kPartitions, [&](std::size_t p) { KeepFirstOfPartition(p); });
  // The kept indices in order, gathered block by block by all threads.
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::size_t> start(blocks + 1, 0);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    const auto first = kept_.begin() + static_cast<std::ptrdiff_t>(b * kBlock);
    const auto last = kept_.begin() + static_cast<std::ptrdiff_t>(std::min(n, (b + 1) * kBlock));
    start[b + 1] = static_cast<std::size_t>(std::count(first, last, std::uint8_t{1}));
  });
  for (std::size_t b = 0; b < blocks; ++b) start[b + 1] += start[b];
  std::vector<std::size_t> kept(start[blocks]);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t next = start[b];
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
      if (kept_[i]) kept[next++] = i;
    }
  });
  return kept;
}

void FirstPerCell::KeepFirstOfPartition(std::size_t partition) {
  auto& seen = seen_[partition];
  seen.clear();  // keeps the buckets
  seen.reserve(cells_.size() / (4 * kPartitions) + 1);
  // Consecutive points (one firing, top to bottom) often share a cell; a repeat of the
  // partition's previous cell cannot be kept whatever the table says, so it skips the lookup.
  std::optional<ClassVoxel> previous;
  for (std::size_t i = 0; i < cells_.size(); ++i) {
    if (partition_[i] != partition) continue;
    if (previous == cells_[i]) continue;
    previous = cells_[i];
    if (seen.insert(cells_[i]).second) kept_[i] = 1;
  }
}

}  // namespace dammloam
