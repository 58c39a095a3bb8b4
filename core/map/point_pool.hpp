#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/map/map_point.hpp"

namespace dammloam {

// The map's points in slots of fixed pages: a voxel's points are one run of slots that never
// crosses a page. Pages are never moved or given back while the map lives (a crop's holes are
// reused), so the map grows without copying itself and without the large allocations whose
// release leaves the C library keeping tens of MiB for later (its dynamic mmap threshold).
class PointPool {
 public:
  static constexpr int kPageBits = 15;  // 32768 slots, 1.25 MiB of 40-byte points per page
  static constexpr std::size_t kPageSlots = std::size_t{1} << kPageBits;

  MapPoint* At(std::uint32_t slot) { return pages_[slot >> kPageBits].data() + (slot & kMask); }
  const MapPoint* At(std::uint32_t slot) const {
    return pages_[slot >> kPageBits].data() + (slot & kMask);
  }
  // Slots handed out so far: [0, end()), holes and page tails included.
  std::size_t end() const { return end_; }

  // Whether the run [first, first + count) can take `extra` more slots where it is: it ends the
  // pool and its page has room.
  bool CanExtend(std::uint32_t first, std::size_t count, std::size_t extra) const {
    return first + count == end_ && (first & kMask) + count + extra <= kPageSlots;
  }
  // The first slot of a run of `count` slots at `from` or, when that would cross a page, at the
  // next page's start. Reserves nothing: Compact places runs with it, Append hands them out.
  static std::uint32_t Place(std::size_t from, std::size_t count) {
    const std::size_t page_end = (from | kMask) + 1;
    return static_cast<std::uint32_t>(from + count <= page_end ? from : page_end);
  }
  // Hands out `count` slots (at most a page) at the end and returns the first.
  std::uint32_t Append(std::size_t count) {
    const std::uint32_t first = Place(end_, count);
    end_ = first + count;
    while (pages_.size() * kPageSlots < end_) pages_.emplace_back(kPageSlots);
    return first;
  }
  // Slots from `end` on are free again (after a compaction); their pages are kept for reuse.
  void Truncate(std::size_t end) { end_ = end; }
  void Clear() {
    pages_.clear();
    end_ = 0;
  }

 private:
  static constexpr std::size_t kMask = kPageSlots - 1;
  std::vector<std::vector<MapPoint>> pages_;
  std::size_t end_ = 0;
};

}  // namespace dammloam
