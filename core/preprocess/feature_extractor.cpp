#include "core/preprocess/feature_extractor.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/preprocess/normal_map.hpp"
#include "core/preprocess/range_image.hpp"

namespace dammloam {
namespace {

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

template <typename T>
void DiscardIfInconsistent(std::vector<T>& field, std::size_t n) {
  if (field.size() != n) field.clear();
}

// Point i passes: finite (point and time) and within [min_range, max_range]. The scan's
// optional fields are already consistent (empty or one per point).
struct ValidPoint {
  const Scan& scan;
  double min2, max2;
  ValidPoint(const Scan& s, double min_range, double max_range)
      : scan(s), min2(min_range * min_range), max2(max_range * max_range) {}
  bool operator()(std::size_t i) const {
    const double r2 = scan.points[i].squaredNorm();  // NaN/inf fail both comparisons below
    return r2 >= min2 && r2 <= max2 && scan.points[i].allFinite() &&
           (scan.times.size() != scan.points.size() || std::isfinite(scan.times[i]));
  }
};

// Compacts every per-point vector to the points that pass; returns how many were dropped.
std::size_t RemoveInvalidPoints(Scan& scan, double min_range, double max_range) {
  const std::size_t n = scan.points.size();
  DiscardIfInconsistent(scan.intensities, n);
  DiscardIfInconsistent(scan.times, n);
  DiscardIfInconsistent(scan.rings, n);
  const ValidPoint keep(scan, min_range, max_range);
  // Where the first point to drop is (n: none), found by all threads: the points before it
  // stay where they are.
  const std::size_t first_dropped = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 4096), n,
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t first) {
        for (std::size_t i = range.begin(); i < std::min(range.end(), first); ++i) {
          if (!keep(i)) return i;
        }
        return first;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  std::size_t out = first_dropped;
  for (std::size_t i = first_dropped; i < n; ++i) {
    if (!keep(i)) continue;
    if (out != i) {
      scan.points[out] = scan.points[i];
      if (!scan.intensities.empty()) scan.intensities[out] = scan.intensities[i];
      if (!scan.times.empty()) scan.times[out] = scan.times[i];
      if (!scan.rings.empty()) scan.rings[out] = scan.rings[i];
    }
    ++out;
  }
  scan.points.resize(out);
  if (!scan.intensities.empty()) scan.intensities.resize(out);
  if (!scan.times.empty()) scan.times.resize(out);
  if (!scan.rings.empty()) scan.rings.resize(out);
  return n - out;
}

}  // namespace

FeatureExtractor::FeatureExtractor(const PreprocessConfig& config, const SensorModel& sensor)
    : config_(config),
      sensor_(sensor),
      classifier_(config.classifier),
      min_range_(std::max(config.min_range, sensor.min_range)),
      max_range_(sensor.max_range > 0.0 ? std::min(config.max_range, sensor.max_range)
                                        : config.max_range) {}

std::vector<std::uint8_t> FeatureExtractor::KeptPoints(const Scan& scan) const {
  const ValidPoint keep(scan, min_range_, max_range_);
  std::vector<std::uint8_t> kept(scan.points.size());
  for (std::size_t i = 0; i < kept.size(); ++i) kept[i] = keep(i) ? 1 : 0;
  return kept;
}

ClassifiedScan FeatureExtractor::Extract(Scan scan, const Eigen::Matrix3d& R_world_sensor) const {
  FeatureWorkspace workspace;
  return Extract(std::move(scan), R_world_sensor, workspace);
}

ClassifiedScan FeatureExtractor::Extract(Scan scan, const Eigen::Matrix3d& R_world_sensor,
                                         FeatureWorkspace& workspace) const {
  ClassifiedScan out;
  out.dropped_invalid = RemoveInvalidPoints(scan, min_range_, max_range_);
  out.scan = std::move(scan);
  const auto& points = out.scan.points;
  const std::size_t n = points.size();

  auto start = std::chrono::steady_clock::now();
  if (!workspace.image) workspace.image.emplace(config_.range_image, sensor_);
  RangeImage& image = *workspace.image;
  image.Build(points, out.scan.rings);
  out.projection_ms = MillisecondsSince(start);

  start = std::chrono::steady_clock::now();
  if (!workspace.normal_map) workspace.normal_map.emplace(config_.normals);
  NormalMap& normal_map = *workspace.normal_map;
  normal_map.Build(image);
  out.normals_ms = MillisecondsSince(start);

  start = std::chrono::steady_clock::now();
  classifier_.Classify(normal_map, R_world_sensor, workspace.classifier);
  const std::vector<PointClass>& pixel_labels = workspace.classifier.labels;
  out.labels.resize(n);
  out.normals.resize(n);
  const double inherit2 =
      config_.range_image.max_inherit_distance * config_.range_image.max_inherit_distance;
  const auto& pixel_normals = normal_map.normals();
  // Every point's label and normal written once (no zero fill first), counted on the way.
  out.class_counts = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 4096), ClassCounts{},
      [&](const tbb::blocked_range<std::size_t>& range, ClassCounts counts) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const int pixel = image.pixel_of(i);
          const int winner = pixel < 0 ? -1 : image.index_of_pixel(pixel);
          const bool labelled =
              winner == static_cast<int>(i) ||
              (winner >= 0 &&
               !((points[i] - points[static_cast<std::size_t>(winner)]).squaredNorm() > inherit2));
          out.labels[i] =
              labelled ? pixel_labels[static_cast<std::size_t>(pixel)] : PointClass::Unknown;
          out.normals[i] = labelled ? pixel_normals[static_cast<std::size_t>(pixel)]
                                    : Eigen::Vector3f::Zero();
          ++counts[Index(out.labels[i])];
        }
        return counts;
      },
      [](ClassCounts a, const ClassCounts& b) {
        for (std::size_t c = 0; c < a.size(); ++c) a[c] += b[c];
        return a;
      });
  out.classification_ms = MillisecondsSince(start);
  return out;
}

}  // namespace dammloam
