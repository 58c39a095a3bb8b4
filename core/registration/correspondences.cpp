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
  CorrespondenceBuffers buffers;
  CorrespondenceSet out;
  FindCorrespondences(source_world, labels, map, max_distance, mode, unknown_defers_to_map, times,
                      subset, memory, buffers, out);
  return out;
}

void FindCorrespondences(const std::vector<Eigen::Vector3d>& source_world,
                         const std::vector<PointClass>& labels, const VoxelHashMap& map,
                         double max_distance, RegistrationMode mode, bool unknown_defers_to_map,
                         const std::vector<float>& times, const SourceSubset& subset,
                         SearchMemory* memory, CorrespondenceBuffers& buffers,
                         CorrespondenceSet& out) {
  const std::size_t n = source_world.size();
  // Fixed blocks: each block counts its pairs while it searches, so that the pairs can then be
  // written in source order by all threads at once (a serial pass over the matches cost as
  // much as a tenth of the registration on two cores).
  constexpr std::size_t kBlock = 256;
  constexpr std::size_t kPlanar = 0, kPoint = 1, kSearched = 2;  // a block's counts
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  buffers.match.assign(n, nullptr);
  buffers.kind.assign(n, static_cast<std::uint8_t>(PairKind::kNone));
  buffers.counts.assign(blocks, {0, 0, 0});
  const MapPoint** const match = buffers.match.data();
  PairKind* const kind = reinterpret_cast<PairKind*>(buffers.kind.data());
  std::array<std::size_t, 3>* const counts = buffers.counts.data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const auto& range) {
    for (std::size_t block = range.begin(); block < range.end(); ++block) {
      std::array<std::size_t, 3>& count = counts[block];
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
          ++count[kSearched];
          if (memory != nullptr) {
            memory->answer[i] = found;
            memory->searched_at[i] = source_world[i];
            memory->searched[i] = 1;
          }
        }
        if (q == nullptr) continue;
        match[i] = q;
        kind[i] = Classify(mode, label, *q);
        ++count[kind[i] == PairKind::kPlanar ? kPlanar : kPoint];
      }
    }
  });
  // Where each block's pairs start in the output.
  buffers.starts.resize(blocks);
  std::array<std::size_t, 3>* const starts = buffers.starts.data();
  std::array<std::size_t, 3> total{0, 0, 0};
  for (std::size_t block = 0; block < blocks; ++block) {
    starts[block] = total;
    for (std::size_t k = 0; k < 3; ++k) total[k] += counts[block][k];
  }
  out.searched_points = total[kSearched];
  out.planar.resize(total[kPlanar]);
  out.point.resize(total[kPoint]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const auto& range) {
    for (std::size_t block = range.begin(); block < range.end(); ++block) {
      std::size_t next_planar = starts[block][kPlanar], next_point = starts[block][kPoint];
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
}

}  // namespace dammloam
