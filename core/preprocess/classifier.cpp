#include "core/preprocess/classifier.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace dammloam {
namespace {

constexpr double kMajorityEpsilon = 1e-9;  // 2/3 * 9 must accept 6 votes despite rounding

// acos to within 7e-5 rad (Abramowitz & Stegun 4.4.45): the edge test compares a mean of
// angles with a 15 deg threshold, and libm's acos was the classifier's largest cost.
float FastAcos(float x) {
  const float a = std::min(std::abs(x), 1.0f);
  const float f = std::sqrt(1.0f - a) *
                  (1.5707288f + a * (-0.2121144f + a * (0.0742610f + a * -0.0187293f)));
  return x < 0.0f ? std::numbers::pi_v<float> - f : f;
}

// Mean squared chord over all pairs of `count` unit vectors with the given sum.
double MeanSquaredChord(int count, const Eigen::Vector3d& sum) {
  const double pairs = 0.5 * count * (count - 1);
  return std::max(0.0, double(count) * count - sum.squaredNorm()) / pairs;
}

}  // namespace

Classifier::Classifier(const ClassifierConfig& config)
    : config_(config), edge_angle_rad_(config.edge_angle_deg * std::numbers::pi / 180.0) {}

// Mean of the pairwise angles, decided with cheap exact bounds before any acos. For unit
// vectors an angle lies between its chord c and (pi/2) c, and the sum of squared chords over
// all pairs is n^2 - |sum|^2. So: an upper bound of the mean angle from the root-mean-square
// chord below the threshold -> not an edge (flat windows, most of a scan); mean chord above
// it -> an edge (clear corners); only the windows in between pay for the acos of every pair.
bool Classifier::FlatByChordBound(double mean_chord2) const {
  // (pi/2) sqrt(mean_chord2) <= threshold, squared: no square root on most of a scan's windows.
  constexpr double kHalfPi2 = 0.25 * std::numbers::pi * std::numbers::pi;
  return kHalfPi2 * mean_chord2 <= edge_angle_rad_ * edge_angle_rad_;
}

bool Classifier::MeanPairwiseAngleExceeds(const Eigen::Vector3f* normals, int count,
                                          double mean_chord2) const {
  const double pairs = 0.5 * count * (count - 1);

  // Tighter: the angle 2 asin(c / 2) is convex in the chord c with value 0 at 0, so every
  // pair's angle is at most c times the angle/chord ratio of the widest pair. Noisy but flat
  // windows end here without a square root per pair.
  float max_chord2 = 0.0f;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      max_chord2 = std::max(max_chord2, (normals[i] - normals[j]).squaredNorm());
    }
  }
  const double max_chord = std::sqrt(static_cast<double>(max_chord2));
  const double slope =
      max_chord > 1e-9 ? 2.0 * std::asin(std::min(1.0, 0.5 * max_chord)) / max_chord : 1.0;
  if (slope * std::sqrt(mean_chord2) <= edge_angle_rad_) return false;
  // And from below: angle >= chord >= chord^2 / widest chord, so clear corners end here too.
  if (mean_chord2 > edge_angle_rad_ * max_chord) return true;

  double chord_sum = 0.0;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) chord_sum += (normals[i] - normals[j]).norm();
  }
  if (chord_sum / pairs > edge_angle_rad_) return true;

  double angle_sum = 0.0;
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      angle_sum += FastAcos(normals[i].dot(normals[j]));
    }
  }
  return angle_sum / pairs > edge_angle_rad_;
}

// The planar class a single gravity-aligned normal votes for (Unknown: none).
PointClass Classifier::Vote(const Eigen::Vector3f& n) const {
  const float k = static_cast<float>(config_.dominance);
  const Eigen::Vector3f a = n.cwiseAbs();
  if (a.z() >= k * a.x() && a.z() >= k * a.y()) {
    return n.z() > 0.0f ? PointClass::Ground : PointClass::Roof;
  }
  if ((a.x() >= k * a.y() && a.x() >= k * a.z()) || (a.y() >= k * a.x() && a.y() >= k * a.z())) {
    return PointClass::Wall;
  }
  return PointClass::Unknown;
}

PointClass Classifier::ClassifyWindow(const Eigen::Vector3f* normals, int count,
                                      bool centre_valid) const {
  const int n = std::min(count, 9);
  WindowSummary window;
  for (int i = 0; i < n; ++i) window.Add(normals[i], Vote(normals[i]));
  return Decide(window, centre_valid, [&](Eigen::Vector3f* out) {
    std::copy(normals, normals + n, out);
    return n;
  });
}

template <typename Gather>
PointClass Classifier::Decide(const WindowSummary& window, bool centre_valid,
                              Gather gather) const {
  const int count = window.count();
  if (count < config_.min_valid_normals || count == 0) return PointClass::Unknown;
  if (count >= 2) {
    const double mean_chord2 = MeanSquaredChord(count, window.sum);
    if (!FlatByChordBound(mean_chord2)) {
      Eigen::Vector3f normals[9];
      if (MeanPairwiseAngleExceeds(normals, gather(normals), mean_chord2)) return PointClass::Edge;
    }
  }
  if (config_.require_centre_normal && !centre_valid) return PointClass::Unknown;
  const double needed = config_.majority * count - kMajorityEpsilon;
  for (const PointClass c : {PointClass::Ground, PointClass::Roof, PointClass::Wall}) {
    if (window.votes(c) >= needed) return c;
  }
  return PointClass::Unknown;
}

std::vector<PointClass> Classifier::Classify(const NormalMap& normal_map,
                                             const Eigen::Matrix3d& R_world_sensor) const {
  Buffers buffers;
  Classify(normal_map, R_world_sensor, buffers);
  return std::move(buffers.labels);
}

void Classifier::Classify(const NormalMap& normal_map, const Eigen::Matrix3d& R_world_sensor,
                          Buffers& buffers) const {
  const int rows = normal_map.rows();
  const int cols = normal_map.cols();
  const auto& valid = normal_map.validity();
  const auto& normals = normal_map.normals();
  const Eigen::Matrix3f R = R_world_sensor.cast<float>();

  // Gravity-aligned normals and their votes once per pixel, not once per window they are in.
  std::vector<Eigen::Vector3f>& aligned = buffers.aligned;
  std::vector<PointClass>& pixel_votes = buffers.pixel_votes;
  aligned.resize(normals.size());
  pixel_votes.assign(normals.size(), PointClass::Unknown);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, normals.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        if (!valid[i]) continue;
                        aligned[i] = R * normals[i];
                        pixel_votes[i] = Vote(aligned[i]);
                      }
                    });

  std::vector<PointClass>& labels = buffers.labels;
  labels.assign(normals.size(), PointClass::Unknown);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 4), [&](const tbb::blocked_range<int>& rr) {
    std::vector<WindowSummary>& columns = buffers.columns.local();
    columns.resize(static_cast<std::size_t>(cols));
    for (int r = rr.begin(); r < rr.end(); ++r) {
      const int first_row = std::max(r - 1, 0), last_row = std::min(r + 1, rows - 1);
      // Per column, the window's rows; a window is then three neighbouring columns.
      for (int c = 0; c < cols; ++c) {
        WindowSummary& column = columns[static_cast<std::size_t>(c)];
        column = WindowSummary{};
        for (int wr = first_row; wr <= last_row; ++wr) {
          const std::size_t pixel = static_cast<std::size_t>(wr) * cols + c;
          if (valid[pixel]) column.Add(aligned[pixel], pixel_votes[pixel]);
        }
      }
      for (int c = 0; c < cols; ++c) {
        // The 3x3 window, rows top to bottom, columns left to right, wrapping around 360 deg.
        const int window_cols[3] = {c == 0 ? cols - 1 : c - 1, c, c == cols - 1 ? 0 : c + 1};
        WindowSummary window = columns[static_cast<std::size_t>(window_cols[0])];
        window += columns[static_cast<std::size_t>(window_cols[1])];
        window += columns[static_cast<std::size_t>(window_cols[2])];
        const auto gather = [&](Eigen::Vector3f* out) {
          int count = 0;
          for (int wr = first_row; wr <= last_row; ++wr) {
            const std::size_t row_start = static_cast<std::size_t>(wr) * cols;
            for (const int wc : window_cols) {
              const std::size_t pixel = row_start + static_cast<std::size_t>(wc);
              if (valid[pixel]) out[count++] = aligned[pixel];
            }
          }
          return count;
        };
        const std::size_t centre = static_cast<std::size_t>(r) * cols + c;
        labels[centre] = Decide(window, valid[centre] != 0, gather);
      }
    }
  });
}

}  // namespace dammloam
