#include "core/preprocess/range_image.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

namespace dammloam {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxRows = 1024;  // no spinning LiDAR has more beams
constexpr std::uint64_t kNoOwner = ~std::uint64_t{0};  // a pixel no point fell into
constexpr double kAngleTableStep = 0.005 * std::numbers::pi / 180.0;  // 0.005 deg bins

int PositiveOr(int value, int fallback) { return value > 0 ? value : fallback; }

int AutoColumns(int sensor_columns, int rows, const RangeImageConfig& config) {
  int columns = PositiveOr(sensor_columns, 1024);
  if (config.max_auto_cols > 0) columns = std::min(columns, config.max_auto_cols);
  if (config.max_auto_pixels > 0 && rows > 0) {
    const int budget = std::max(config.max_auto_pixels / rows, std::max(config.min_auto_cols, 1));
    columns = std::min(columns, budget);
  }
  return columns;
}

bool Projectable(const Eigen::Vector3d& p) {
  const double r2 = p.squaredNorm();
  return std::isfinite(r2) && r2 > 0.0;
}

double Elevation(const Eigen::Vector3d& p) { return std::atan2(p.z(), p.head<2>().norm()); }

}  // namespace

RangeImage::RangeImage(const RangeImageConfig& config, const SensorModel& sensor)
    : configured_rows_(PositiveOr(config.rows, PositiveOr(sensor.rings, 64))),
      rows_(configured_rows_),
      cols_(PositiveOr(config.cols, AutoColumns(sensor.columns, configured_rows_, config))) {
  for (const double deg : sensor.vertical_angles_deg) {
    if (std::isfinite(deg)) vertical_angles_rad_.push_back(deg * std::numbers::pi / 180.0);
  }
  // Rows run from the highest beam down, whatever order the angles were listed in.
  std::sort(vertical_angles_rad_.begin(), vertical_angles_rad_.end(), std::greater<>());
  BuildAngleTable();
}

void RangeImage::BuildAngleTable() {
  if (vertical_angles_rad_.size() < 2) return;
  table_min_ = vertical_angles_rad_.back();
  const double span = vertical_angles_rad_.front() - table_min_;
  const auto bins = static_cast<std::size_t>(std::ceil(span / kAngleTableStep)) + 1;
  table_step_ = kAngleTableStep;
  angle_table_.resize(bins);
  // Angles are sorted descending, so the nearest row for increasing elevation only decreases.
  int row = static_cast<int>(vertical_angles_rad_.size()) - 1;
  for (std::size_t b = 0; b < bins; ++b) {
    const double phi = table_min_ + (static_cast<double>(b) + 0.5) * table_step_;
    while (row > 0 && std::abs(vertical_angles_rad_[row - 1] - phi) <
                          std::abs(vertical_angles_rad_[row] - phi)) {
      --row;
    }
    angle_table_[b] = row;
  }
}

int RangeImage::ColumnOf(const Eigen::Vector3d& p) const {
  const double azimuth = std::atan2(p.y(), p.x());
  const int c = static_cast<int>(std::floor((azimuth + std::numbers::pi) / kTwoPi * cols_));
  return c >= cols_ ? c - cols_ : (c < 0 ? c + cols_ : c);
}

void RangeImage::ComputeRowsFromRings(const std::vector<std::int16_t>& rings) {
  // A corrupt ring must not blow the image up: beyond kMaxRows the point is not projected.
  const int max_ring = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, rings.size(), 4096), -1,
      [&](const tbb::blocked_range<std::size_t>& range, int highest) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const bool usable = point_row_[i] == 0 && rings[i] >= 0 && rings[i] < kMaxRows;
          point_row_[i] = usable ? rings[i] : -1;
          if (usable) highest = std::max<int>(highest, rings[i]);
        }
        return highest;
      },
      [](int a, int b) { return std::max(a, b); });
  rows_ = std::max(configured_rows_, max_ring + 1);
}

void RangeImage::ComputeRowsFromAngles(const std::vector<Eigen::Vector3d>& points) {
  rows_ = static_cast<int>(vertical_angles_rad_.size());
  const int last_bin = static_cast<int>(angle_table_.size()) - 1;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_row_[i] != 0) continue;
    const double bin = std::floor((Elevation(points[i]) - table_min_) / table_step_);
    point_row_[i] = angle_table_[static_cast<std::size_t>(std::clamp(bin, 0.0, double(last_bin)))];
  }
}

// Unorganised clouds stored ring after ring (KITTI .bin) sweep the azimuth once per ring, so a
// drop of more than pi starts the next ring. Segments shorter than a quarter of an average ring
// are stragglers jittering across the +-pi seam, not rings. Accepted only when the number of
// rings found is within 10 % of the configured rows (KITTI shows 64-65: a partial first ring);
// column-major (firing order) clouds wrap once and fail this test.
bool RangeImage::ComputeRowsFromScanOrder(const std::vector<Eigen::Vector3d>& points) {
  const std::size_t min_ring_points =
      std::max<std::size_t>(8, points.size() / (4 * static_cast<std::size_t>(configured_rows_)));
  int ring = 0;
  std::size_t ring_start = 0;
  double previous = 0.0;
  bool first = true;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_row_[i] < 0) continue;
    const double azimuth = std::atan2(points[i].y(), points[i].x());
    if (!first && previous - azimuth > std::numbers::pi && i - ring_start >= min_ring_points) {
      ++ring;
      ring_start = i;
    }
    first = false;
    previous = azimuth;
    point_row_[i] = ring;
  }
  const int found = ring + 1;
  if (first || 10 * found > 11 * configured_rows_ || 10 * found < 9 * configured_rows_) {
    for (int& row : point_row_) row = std::min(row, 0);  // back to "pending"
    return false;
  }
  rows_ = std::max(configured_rows_, found);
  return true;
}

void RangeImage::ComputeRowsFromSpan(const std::vector<Eigen::Vector3d>& points) {
  rows_ = configured_rows_;
  // Two passes (span, then bins) compute each elevation twice; only unorganised clouds without
  // known beam angles take this path.
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -lowest;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_row_[i] != 0) continue;
    const double phi = Elevation(points[i]);
    lowest = std::min(lowest, phi);
    highest = std::max(highest, phi);
  }
  const double span = highest - lowest;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_row_[i] != 0) continue;
    const double t = span > 0.0 ? (highest - Elevation(points[i])) / span : 0.0;
    point_row_[i] = std::min(rows_ - 1, static_cast<int>(t * rows_));
  }
}

void RangeImage::Build(const std::vector<Eigen::Vector3d>& points,
                       const std::vector<std::int16_t>& rings) {
  const std::size_t n = points.size();
  // point_row_: -1 = not projectable, 0 = pending (the row computations overwrite it).
  point_row_.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      point_row_[i] = Projectable(points[i]) ? 0 : -1;
    }
  });

  if (rings.size() == n && n > 0) {
    ComputeRowsFromRings(rings);
  } else if (!angle_table_.empty()) {
    ComputeRowsFromAngles(points);
  } else if (!ComputeRowsFromScanOrder(points)) {
    ComputeRowsFromSpan(points);
  }

  const std::size_t pixels = static_cast<std::size_t>(rows_) * cols_;
  index_.assign(pixels, -1);
  pixels_.assign(pixels, Pixel{});
  pixel_of_.assign(n, -1);

  // Nearest wins, decided in parallel: a pixel keeps the minimum of (range, index) packed into
  // one word (a non-negative float's bits order like the float), so the winner does not depend
  // on which thread got there first, and equal ranges go to the lower index.
  owner_.assign(pixels, kNoOwner);
  std::uint64_t* const owner = owner_.data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (point_row_[i] < 0) continue;
      const int pixel = Flat(point_row_[i], ColumnOf(points[i]));
      pixel_of_[i] = pixel;
      const std::uint64_t key =
          (std::uint64_t{std::bit_cast<std::uint32_t>(static_cast<float>(points[i].norm()))}
           << 32) |
          static_cast<std::uint32_t>(i);
      std::atomic_ref<std::uint64_t> slot(owner[static_cast<std::size_t>(pixel)]);
      std::uint64_t current = slot.load(std::memory_order_relaxed);
      while (key < current &&
             !slot.compare_exchange_weak(current, key, std::memory_order_relaxed)) {
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels, 4096), [&](const auto& range) {
    for (std::size_t pixel = range.begin(); pixel < range.end(); ++pixel) {
      if (owner[pixel] == kNoOwner) continue;
      const auto winner = static_cast<std::uint32_t>(owner[pixel] & 0xffffffffu);
      index_[pixel] = static_cast<int>(winner);
      pixels_[pixel] = {points[winner].cast<float>(),
                        std::bit_cast<float>(static_cast<std::uint32_t>(owner[pixel] >> 32))};
    }
  });
}

}  // namespace dammloam
