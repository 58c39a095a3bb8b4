#include "core/registration/correspondences.hpp"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace dammloam {

namespace {
enum class PairKind : std::uint8_t { kNone, kPlanar, kPoint };

PairKind Classify(RegistrationMode mode, PointClass source_label, const MapPoint& target) {
  const bool has_normal = target.normal.squaredNorm() > 0.5f;
  switch (mode) {
    case RegistrationMode::kPointToPoint: return PairKind::kPoint;
    case RegistrationMode::kPlaneOnly: return has_normal ? PairKind::kPlanar : PairKind::kNone;
    case RegistrationMode::kFull:
    case RegistrationMode::kFullRemap:
    case RegistrationMode::kClassesNoDegeneracy: break;
  }
  // An unknown source point has taken the map point's class (see FindCorrespondences).
  const PointClass surface = source_label == PointClass::Unknown ? target.label : source_label;
  return IsPlanar(surface) && has_normal ? PairKind::kPlanar : PairKind::kPoint;
}
}  // namespace

CorrespondenceSet FindCorrespondences(const std::vector<Eigen::Vector3d>& source_world,
                                      const std::vector<PointClass>& labels,
                                      const VoxelHashMap& map, double max_distance,
                                      RegistrationMode mode, bool unknown_defers_to_map,
                                      const std::vector<float>& times,
                                      const SourceSubset& subset, SearchMemory* memory) {
  const std::size_t n = source_world.size();
  // Fixed blocks: each block counts its pairs while it searches, so that the pairs can then be
  // written in source order by all threads at once (a serial pass over the matches cost as
  // much as a tenth of the registration on two cores).
  constexpr std::size_t kBlock = 256;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<const MapPoint*> match(n, nullptr);
  std::vector<PairKind> kind(n, PairKind::kNone);
  struct BlockCounts {
    std::size_t planar = 0, point = 0, searched = 0;
  };
  std::vector<BlockCounts> counts(blocks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const auto& range) {
    for (std::size_t block = range.begin(); block < range.end(); ++block) {
      BlockCounts& count = counts[block];
      for (std::size_t i = block * kBlock; i < std::min(n, (block + 1) * kBlock); ++i) {
        if (!subset.Contains(i)) continue;
        const PointClass label = i < labels.size() ? labels[i] : PointClass::Unknown;
        const MapPoint* q = nullptr;
        if (memory != nullptr && memory->searched[i] &&
            map.StillNearest(memory->answer[i], memory->searched_at[i], source_world[i],
                             max_distance)) {
          q = memory->answer[i].point;
        } else {
          const bool any_class =
              !ClassWise(mode) || (unknown_defers_to_map && label == PointClass::Unknown);
          const std::optional<PointClass> wanted =
              any_class ? std::nullopt : std::optional<PointClass>(label);
          const VoxelHashMap::NearestPoint found =
              map.Nearest(source_world[i], wanted, max_distance);
          q = found.point;
          ++count.searched;
          if (memory != nullptr) {
            memory->answer[i] = found;
            memory->searched_at[i] = source_world[i];
            memory->searched[i] = 1;
          }
        }
        if (q == nullptr) continue;
        match[i] = q;
        kind[i] = Classify(mode, label, *q);
        ++(kind[i] == PairKind::kPlanar ? count.planar : count.point);
      }
    }
  });
  // Where each block's pairs start in the output.
  std::vector<BlockCounts> starts(blocks);
  CorrespondenceSet out;
  BlockCounts total;
  for (std::size_t block = 0; block < blocks; ++block) {
    starts[block] = total;
    total.planar += counts[block].planar;
    total.point += counts[block].point;
    total.searched += counts[block].searched;
  }
  out.searched_points = total.searched;
  out.planar.resize(total.planar);
  out.point.resize(total.point);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const auto& range) {
    for (std::size_t block = range.begin(); block < range.end(); ++block) {
      std::size_t next_planar = starts[block].planar, next_point = starts[block].point;
      for (std::size_t i = block * kBlock; i < std::min(n, (block + 1) * kBlock); ++i) {
        if (kind[i] == PairKind::kNone) continue;
        const bool planar = kind[i] == PairKind::kPlanar;
        (planar ? out.planar[next_planar++] : out.point[next_point++]) =
            Correspondence{source_world[i], match[i]->position,
                           match[i]->normal.cast<double>().normalized(),
                           i < times.size() ? double{times[i]} : 0.0};
      }
    }
  });
  return out;
}

}  // namespace dammloam
