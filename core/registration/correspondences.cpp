#include "core/registration/correspondences.hpp"

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
  std::vector<const MapPoint*> match(n, nullptr);
  std::vector<PairKind> kind(n, PairKind::kNone);
  std::vector<std::uint8_t> searched(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
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
        const VoxelHashMap::NearestPoint found = map.Nearest(source_world[i], wanted, max_distance);
        q = found.point;
        searched[i] = 1;
        if (memory != nullptr) {
          memory->answer[i] = found;
          memory->searched_at[i] = source_world[i];
          memory->searched[i] = 1;
        }
      }
      if (q == nullptr) continue;
      match[i] = q;
      kind[i] = Classify(mode, label, *q);
    }
  });
  CorrespondenceSet out;
  for (std::size_t i = 0; i < n; ++i) {
    out.searched_points += searched[i];
    if (kind[i] == PairKind::kNone) continue;
    const Correspondence c{source_world[i], match[i]->position,
                           match[i]->normal.cast<double>().normalized(),
                           i < times.size() ? double{times[i]} : 0.0};
    (kind[i] == PairKind::kPlanar ? out.planar : out.point).push_back(c);
  }
  return out;
}

}  // namespace dammloam
