#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/scan.hpp"
#include "core/preprocess/classified_scan.hpp"
#include "core/preprocess/classifier.hpp"
#include "core/preprocess/normal_map.hpp"
#include "core/preprocess/preprocess_config.hpp"
#include "core/preprocess/range_image.hpp"

namespace dammloam {

// The buffers of one thread's feature stage, kept between its scans: with them a scan of the
// same sensor allocates only its own output (issue 57: no allocation per scan).
struct FeatureWorkspace {
  std::optional<RangeImage> image;
  std::optional<NormalMap> normal_map;
  Classifier::Buffers classifier;
};

// The feature stage of DAMM-LOAM (paper Sec. III-A): validation, spherical projection, normal
// map and classification of one scan. Extract() is const and keeps no state between calls, so
// one extractor may serve several threads at once, each with its own workspace.
class FeatureExtractor {
 public:
  FeatureExtractor(const PreprocessConfig& config, const SensorModel& sensor);

  // Drops points that are not finite (point or time) or outside the valid range (the config's
  // interval intersected with the sensor's), keeping every per-point vector consistent, then
  // labels every remaining point and gives it a normal (sensor frame, zero if none).
  // A point that lost its pixel to a nearer one takes the winner's label and normal when it is
  // within max_inherit_distance of it, else Unknown. R_world_sensor: predicted orientation,
  // used to judge up/down and vertical surfaces. Optional per-point fields (intensities, times,
  // rings) whose size is neither 0 nor points.size() are discarded as unusable.
  ClassifiedScan Extract(Scan scan, const Eigen::Matrix3d& R_world_sensor) const;
  // The same in `workspace`'s buffers (bit-identical results).
  ClassifiedScan Extract(Scan scan, const Eigen::Matrix3d& R_world_sensor,
                         FeatureWorkspace& workspace) const;
  // 1 for each point of `scan` that Extract keeps (the others are dropped; the kept keep their
  // order): how an evaluation matches per-point truth to a result's points.
  std::vector<std::uint8_t> KeptPoints(const Scan& scan) const;

 private:
  PreprocessConfig config_;
  SensorModel sensor_;
  Classifier classifier_;
  double min_range_;
  double max_range_;
};

}  // namespace dammloam
