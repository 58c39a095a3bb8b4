#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/registration/correspondences.hpp"
#include "core/registration/shape_cache.hpp"

namespace dammloam {

// What registration keeps between scans: the map's shapes it judged (ShapeCache) and the
// buffers its iterations fill, so that a scan in the steady state allocates nothing there
// (issue 57). Contents between calls mean nothing but `shapes`.
struct RegistrationWorkspace {
  ShapeCache shapes;

  std::vector<Eigen::Vector3d> source_world;
  CorrespondenceSet pairs;
  CorrespondenceSet settled_coarse_pairs;
  SearchMemory search_memory;
  CorrespondenceBuffers search_buffers;

  // The full mode's weak-direction sorting (WeakAware).
  std::vector<Eigen::Vector3d> searched_normals;
  std::vector<Correspondence> shaped, point, unjudged;
  std::vector<std::uint8_t> faces;
  std::vector<std::size_t> facing;
  std::vector<const LocalShape*> shapes_of_pairs;
};

}  // namespace dammloam
