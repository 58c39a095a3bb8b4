#pragma once
#include <Eigen/Core>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/scan.hpp"

namespace dammloam {

// Output of the feature stage (projection, normals, classification), input of registration.
// Every vector is per point of `scan` (same order); points that failed validation (NaN/inf,
// out of range) were removed from `scan` before projection.
struct ClassifiedScan {
  Scan scan;
  std::vector<PointClass> labels;
  std::vector<Eigen::Vector3f> normals;  // unit, sensor frame, facing the sensor; zero if invalid
  ClassCounts class_counts{};
  std::size_t dropped_invalid = 0;        // points removed by validation
  // Stage timings in milliseconds, filled by FeatureExtractor.
  double projection_ms = 0.0;
  double normals_ms = 0.0;
  double classification_ms = 0.0;
};

}  // namespace dammloam
