#include "core/geometry/first_per_cell.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

namespace dammloam {
namespace {

constexpr std::uint64_t kMix = 0x9E3779B97F4A7C15ULL;
constexpr std::size_t kBlock = 4096;  // points per block of the parallel passes

// The tables index buckets by the hash's low bits; partitions take the top bits of a mixed
// copy, or each table would fill only a quarter of its buckets.
std::uint8_t PartitionOf(const ClassVoxel& cell) {
  return static_cast<std::uint8_t>((std::uint64_t{ClassVoxelHash{}(cell)} * kMix) >> 62);
}

// A cache slot from bits that neither the partition (top) nor the tables (low) use.
std::size_t RecentSlotOf(const ClassVoxel& cell, std::size_t slots) {
  return static_cast<std::size_t>((std::uint64_t{ClassVoxelHash{}(cell)} * kMix) >> 40) &
         (slots - 1);
}

}  // namespace

std::vector<std::size_t> FirstPerCell::Select(
    const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
    const std::array<double, kNumPointClasses>& voxel_sizes) {
  std::vector<std::size_t> kept;
  Select(points, labels, voxel_sizes, kept);
  return kept;
}

void FirstPerCell::Select(const std::vector<Eigen::Vector3d>& points,
                          const std::vector<PointClass>& labels,
                          const std::array<double, kNumPointClasses>& voxel_sizes,
                          std::vector<std::size_t>& kept) {
  const std::size_t n = points.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  cells_.resize(n);
  partition_.resize(n);
  // Per block, how many of its points each partition holds.
  std::vector<std::array<std::size_t, kPartitions>>& counts = block_counts_;
  counts.resize(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    const std::size_t end = std::min(n, (b + 1) * kBlock);
    ClassVoxel* const cells = cells_.data();
    std::uint8_t* const partition = partition_.data();
    // Counted in registers: an increment in memory per point waited on the previous one's
    // store whenever neighbouring points share a partition (mostly: they share a cell).
    std::size_t count[kPartitions] = {0, 0, 0, 0};
    static_assert(kPartitions == 4);
    for (std::size_t i = b * kBlock; i < end; ++i) {
      const PointClass label = i < labels.size() ? labels[i] : PointClass::Unknown;
      const std::size_t c = std::min<std::size_t>(Index(label), kNumPointClasses - 1);
      cells[i] = {PointToVoxel(points[i], voxel_sizes[c]), label};
      const std::uint8_t p = PartitionOf(cells[i]);
      partition[i] = p;
      count[0] += p == 0;
      count[1] += p == 1;
      count[2] += p == 2;
      count[3] += p == 3;
    }
    std::copy(count, count + kPartitions, counts[b].begin());
  });
  // Each partition's points, contiguous and in input order: block b's points of partition p
  // start after those of the earlier partitions and of p's earlier blocks.
  std::size_t offset = 0;
  for (std::size_t p = 0; p < kPartitions; ++p) {
    partition_start_[p] = offset;
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t count = counts[b][p];
      counts[b][p] = offset;  // from here on: where block b's points of p go
      offset += count;
    }
  }
  partition_start_[kPartitions] = offset;
  ordered_.resize(n);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::array<std::size_t, kPartitions> next = counts[b];
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
      ordered_[next[partition_[i]]++] = {cells_[i], static_cast<std::uint32_t>(i)};
    }
  });
  kept_.assign(n, 0);
  tbb::parallel_for(std::size_t{0}, kPartitions, [&](std::size_t p) { KeepFirstOfPartition(p); });
  GatherKept(kept);
}

// The kept indices in order, gathered block by block by all threads.
void FirstPerCell::GatherKept(std::vector<std::size_t>& kept) {
  const std::size_t n = kept_.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::size_t>& start = block_starts_;
  start.assign(blocks + 1, 0);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    const auto first = kept_.begin() + static_cast<std::ptrdiff_t>(b * kBlock);
    const auto last = kept_.begin() + static_cast<std::ptrdiff_t>(std::min(n, (b + 1) * kBlock));
    start[b + 1] = static_cast<std::size_t>(std::count(first, last, std::uint8_t{1}));
  });
  for (std::size_t b = 0; b < blocks; ++b) start[b + 1] += start[b];
  kept.resize(start[blocks]);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t next = start[b];
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
      if (kept_[i]) kept[next++] = i;
    }
  });
}

void FirstPerCell::KeepFirstOfPartition(std::size_t partition) {
  auto& seen = seen_[partition];
  seen.clear();  // keeps the buckets
  const std::size_t begin = partition_start_[partition], end = partition_start_[partition + 1];
  // tsl's reserve rebuilds the table even when it is large enough: only when it is not.
  const std::size_t expected = (end - begin) / 4 + 1;
  if (static_cast<float>(seen.bucket_count()) * seen.max_load_factor() < static_cast<float>(expected)) {
    seen.reserve(expected);
  }
  // Neighbouring firings mostly revisit the cells the last few firings filled. A small
  // direct-mapped cache of cells already in the table (L1-resident, unlike the table) answers
  // those without a table lookup; it only ever holds seen cells, so a hit is never a new cell.
  constexpr std::size_t kRecent = 512;
  std::array<ClassVoxel, kRecent> recent;
  recent.fill(ClassVoxel{Voxel::Zero(), static_cast<PointClass>(0xff)});  // no class's cell
  for (std::size_t k = begin; k < end; ++k) {
    const ClassVoxel& cell = ordered_[k].cell;
    ClassVoxel& slot = recent[RecentSlotOf(cell, kRecent)];
    if (slot == cell) continue;
    slot = cell;
    if (seen.insert(cell).second) kept_[ordered_[k].index] = 1;
  }
}

}  // namespace dammloam
