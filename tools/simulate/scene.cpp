#include "tools/simulate/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dammloam::sim {

namespace {
// A primitive covering more cells than this is cheaper to test for every beam.
constexpr double kMaxCellsPerItem = 100.0;

Bounds2d BoundsOf(const Primitive& p) {
  return std::visit([](const auto& shape) { return shape.bounds(); }, p);
}
}  // namespace

void Scene::Build(double cell_size) {
  cell_size_ = cell_size;
  global_items_.clear();
  cell_items_.clear();
  cells_.clear();
  nx_ = ny_ = 0;

  std::vector<std::uint32_t> local;
  Bounds2d all{Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()),
               Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity())};
  for (std::uint32_t i = 0; i < primitives_.size(); ++i) {
    const Bounds2d b = BoundsOf(primitives_[i]);
    const Eigen::Vector2d span = (b.max - b.min) / cell_size_ + Eigen::Vector2d::Ones();
    if (span.x() * span.y() > kMaxCellsPerItem) {
      global_items_.push_back(i);
    } else {
      local.push_back(i);
      all.min = all.min.cwiseMin(b.min);
      all.max = all.max.cwiseMax(b.max);
    }
  }
  if (local.empty()) return;

  grid_min_ = all.min.array() - 1e-6;
  nx_ = static_cast<int>(std::floor((all.max.x() - grid_min_.x()) / cell_size_)) + 1;
  ny_ = static_cast<int>(std::floor((all.max.y() - grid_min_.y()) / cell_size_)) + 1;
  std::vector<std::vector<std::uint32_t>> buckets(static_cast<std::size_t>(nx_) * ny_);
  for (const std::uint32_t i : local) {
    const Bounds2d b = BoundsOf(primitives_[i]);
    const int x0 = static_cast<int>((b.min.x() - grid_min_.x()) / cell_size_);
    const int y0 = static_cast<int>((b.min.y() - grid_min_.y()) / cell_size_);
    const int x1 = std::min(nx_ - 1, static_cast<int>((b.max.x() - grid_min_.x()) / cell_size_));
    const int y1 = std::min(ny_ - 1, static_cast<int>((b.max.y() - grid_min_.y()) / cell_size_));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) buckets[static_cast<std::size_t>(y) * nx_ + x].push_back(i);
  }
  cells_.resize(buckets.size());
  for (std::size_t c = 0; c < buckets.size(); ++c) {
    cells_[c].begin = static_cast<std::uint32_t>(cell_items_.size());
    cell_items_.insert(cell_items_.end(), buckets[c].begin(), buckets[c].end());
    cells_[c].end = static_cast<std::uint32_t>(cell_items_.size());
  }
}

bool Scene::TestPrimitive(std::uint32_t index, const Ray& ray, double t_min, Hit& best) const {
  return std::visit([&](const auto& shape) { return shape.Intersect(ray, t_min, best); },
                    primitives_[index]);
}

std::optional<Hit> Scene::Cast(const Ray& ray, double t_min, double t_max) const {
  Hit best;
  best.t = t_max;
  bool hit = false;
  for (const std::uint32_t i : global_items_) hit |= TestPrimitive(i, ray, t_min, best);
  if (ground_) hit |= ground_->Intersect(ray, t_min, best);
  const double t_before = best.t;
  WalkGrid(ray, t_min, best);
  hit |= best.t < t_before;
  if (!hit) return std::nullopt;
  return best;
}

void Scene::WalkGrid(const Ray& ray, double t_min, Hit& best) const {
  if (cells_.empty()) return;
  // Clip the ray to the grid's x-y rectangle (t is the 3-D ray parameter throughout).
  const Eigen::Vector2d o = ray.origin.head<2>(), d = ray.dir.head<2>();
  const Eigen::Vector2d lo = grid_min_, hi = grid_min_ + cell_size_ * Eigen::Vector2d(nx_, ny_);
  double t0 = t_min, t1 = best.t;
  for (int a = 0; a < 2; ++a) {
    if (std::abs(d[a]) < 1e-15) {
      if (o[a] < lo[a] || o[a] > hi[a]) return;
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return;

  // Amanatides-Woo traversal of the cells the beam's footprint crosses, nearest first.
  const Eigen::Vector2d start = o + t0 * d;
  int cell[2], step[2];
  double t_next[2], t_delta[2];
  for (int a = 0; a < 2; ++a) {
    const int n = a == 0 ? nx_ : ny_;
    cell[a] = std::clamp(static_cast<int>((start[a] - lo[a]) / cell_size_), 0, n - 1);
    if (std::abs(d[a]) < 1e-15) {
      step[a] = 0;
      t_next[a] = t_delta[a] = std::numeric_limits<double>::infinity();
    } else {
      step[a] = d[a] > 0 ? 1 : -1;
      const double boundary = lo[a] + (cell[a] + (step[a] > 0 ? 1 : 0)) * cell_size_;
      t_next[a] = (boundary - o[a]) / d[a];
      t_delta[a] = cell_size_ / std::abs(d[a]);
    }
  }
  while (true) {
    const Cell& c = cells_[static_cast<std::size_t>(cell[1]) * nx_ + cell[0]];
    for (std::uint32_t k = c.begin; k < c.end; ++k) TestPrimitive(cell_items_[k], ray, t_min, best);
    const int a = t_next[0] < t_next[1] ? 0 : 1;
    // Hits found so far are final once the beam leaves the cell beyond them.
    if (best.t <= t_next[a] || t_next[a] > t1) return;
    cell[a] += step[a];
    if (cell[a] < 0 || cell[a] >= (a == 0 ? nx_ : ny_)) return;
    t_next[a] += t_delta[a];
  }
}

}  // namespace dammloam::sim
