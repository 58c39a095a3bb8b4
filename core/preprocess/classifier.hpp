#pragma once
#include <tbb/enumerable_thread_specific.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/preprocess/normal_map.hpp"
#include "core/preprocess/preprocess_config.hpp"

namespace dammloam {

// Normal-based classification (paper Sec. III-A.3) over the 3x3 window of each pixel (rows
// clamped, columns wrapping), judged in a gravity-aligned frame: normals are rotated by
// R_world_sensor first, so "z" is world up even for a tilted or hand-held sensor.
//
// Rule order (first match wins):
//   1. fewer than min_valid_normals valid normals in the window  -> Unknown
//   2. mean pairwise angle between the valid normals > edge angle -> Edge
//      (checked before the planar rules: at a wall-wall corner every normal is horizontal, so
//      the wall vote alone would swallow the corner)
//   3. >= majority of valid normals with dominant z and n_z > 0    -> Ground
//   4. >= majority with dominant z and n_z < 0                      -> Roof
//   5. >= majority with dominant x or y                             -> Wall
//   6. otherwise                                                   -> Unknown
// With require_centre_normal, rules 3-5 also need the centre pixel's own normal to be valid.
// Ground, roof and wall majorities are mutually exclusive, so their order is immaterial.
class Classifier {
  // What rules 1 and 3-5 need of a window, and rule 2 on most windows: the count of valid
  // normals, their sum and their votes. Classify() adds these up from per-column sums; the
  // normals themselves are gathered only where the cheap edge bound cannot decide.
  // A window holds at most nine normals, so its count and its votes per class fit in one byte
  // each and add up as one integer (byte c: votes for class c, top byte: count).
  struct WindowSummary {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::uint64_t tallies = 0;
    int count() const { return static_cast<int>(tallies >> kCountShift); }
    int votes(PointClass c) const { return static_cast<int>((tallies >> (8 * Index(c))) & 0xffu); }
    void Add(const Eigen::Vector3f& normal, PointClass vote) {
      sum += normal.cast<double>();
      tallies += (std::uint64_t{1} << kCountShift) | (std::uint64_t{1} << (8 * Index(vote)));
    }
    WindowSummary& operator+=(const WindowSummary& other) {
      sum += other.sum;
      tallies += other.tallies;
      return *this;
    }
    static constexpr int kCountShift = 56;
  };

 public:
  explicit Classifier(const ClassifierConfig& config);

  // What Classify computes into, kept between scans by its caller (one per thread): no
  // allocation once an image as large has been classified.
  struct Buffers {
    std::vector<PointClass> labels;  // the result: one per pixel, row-major
    std::vector<Eigen::Vector3f> aligned;
    std::vector<PointClass> pixel_votes;
    tbb::enumerable_thread_specific<std::vector<WindowSummary>> columns;
  };

  // One label per pixel, row-major (rows * cols). Labels of empty pixels mean nothing.
  std::vector<PointClass> Classify(const NormalMap& normals,
                                   const Eigen::Matrix3d& R_world_sensor) const;
  // The same into buffers.labels.
  void Classify(const NormalMap& normals, const Eigen::Matrix3d& R_world_sensor,
                Buffers& buffers) const;

  // The rules above for one window of valid, unit, gravity-aligned normals (any count).
  PointClass ClassifyWindow(const Eigen::Vector3f* normals, int count, bool centre_valid) const;

 private:

  PointClass Vote(const Eigen::Vector3f& n) const;
  // gather(Eigen::Vector3f out[9]) -> count writes the window's normals in row-major order.
  template <typename Gather>
  PointClass Decide(const WindowSummary& window, bool centre_valid, Gather gather) const;
  // Rule 2's first bound alone, from the window's mean squared chord between its normals:
  // true when the mean pairwise angle is surely below the edge angle.
  bool FlatByChordBound(double mean_chord2) const;
  // Rule 2 for a window FlatByChordBound could not settle (count >= 2).
  bool MeanPairwiseAngleExceeds(const Eigen::Vector3f* normals, int count,
                                double mean_chord2) const;

  ClassifierConfig config_;
  double edge_angle_rad_;
};

}  // namespace dammloam
