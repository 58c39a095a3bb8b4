#include "tools/simulate/swept_volume.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace dammloam::sim {

namespace {

constexpr double kSweepCell = 1.0;  // metres

// Grown by `margin` on every side, then its bottom raised by `clearance` (actor frames turn
// about z only, so the box's z is the world's).
Box Grown(Box box, double margin, double clearance) {
  box.half_size.array() += margin;
  const double raise = std::min(clearance, 2.0 * box.half_size.z());
  box.center.z() += 0.5 * raise;
  box.half_size.z() -= 0.5 * raise;
  return box;
}

Eigen::Vector2d HalfExtent(const Box& box) {
  return (box.rotation.cwiseAbs() * box.half_size).head<2>();
}

int Cell(double value, double origin, int count) {
  return std::clamp(static_cast<int>(std::floor((value - origin) / kSweepCell)), 0, count - 1);
}

}  // namespace

SweptVolume::SweptVolume(const ActorSet& actors, double t_from, double t_to, double step, double margin,
                         double clearance) {
  const int steps = std::max(1, static_cast<int>(std::ceil((t_to - t_from) / step)));
  for (std::size_t i = 0; i < actors.size(); ++i) {
    std::optional<Box> last;
    for (int k = 0; k <= steps; ++k) {
      const std::optional<ActorFootprint> f = actors.FootprintAt(i, t_from + (t_to - t_from) * k / steps);
      if (!f) continue;
      // A standing actor would otherwise add the same body at every sample.
      if (last && (f->box.center - last->center).norm() < 0.02 && f->box.rotation.isApprox(last->rotation, 1e-3)) {
        continue;
      }
      swept_.push_back(Grown(f->box, margin, clearance));
      last = f->box;
    }
    if (const auto f = actors.FootprintAt(i, t_to)) now_.push_back(Grown(f->box, margin, clearance));
  }
  if (swept_.empty()) return;
  Eigen::Vector2d lo = swept_.front().center.head<2>(), hi = lo;
  for (const Box& b : swept_) {
    lo = lo.cwiseMin(b.center.head<2>() - HalfExtent(b));
    hi = hi.cwiseMax(b.center.head<2>() + HalfExtent(b));
  }
  grid_min_ = lo;
  nx_ = static_cast<int>((hi.x() - lo.x()) / kSweepCell) + 1;
  ny_ = static_cast<int>((hi.y() - lo.y()) / kSweepCell) + 1;
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  for (std::size_t i = 0; i < swept_.size(); ++i) {
    const Eigen::Vector2d a = swept_[i].center.head<2>() - HalfExtent(swept_[i]);
    const Eigen::Vector2d b = swept_[i].center.head<2>() + HalfExtent(swept_[i]);
    for (int y = Cell(a.y(), lo.y(), ny_); y <= Cell(b.y(), lo.y(), ny_); ++y) {
      for (int x = Cell(a.x(), lo.x(), nx_); x <= Cell(b.x(), lo.x(), nx_); ++x) {
        cells_[static_cast<std::size_t>(y) * nx_ + x].push_back(i);
      }
    }
  }
}

bool SweptVolume::Inside(const Box& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d local = box.rotation.transpose() * (p - box.center);
  return (local.cwiseAbs() - box.half_size).maxCoeff() <= 0.0;
}

const std::vector<std::size_t>& SweptVolume::Near(const Eigen::Vector3d& p) const {
  static const std::vector<std::size_t> kNone;
  if (cells_.empty()) return kNone;
  const double x = (p.x() - grid_min_.x()) / kSweepCell, y = (p.y() - grid_min_.y()) / kSweepCell;
  if (x < 0.0 || y < 0.0 || x >= nx_ || y >= ny_) return kNone;
  return cells_[static_cast<std::size_t>(Cell(p.y(), grid_min_.y(), ny_)) * nx_ +
                static_cast<std::size_t>(Cell(p.x(), grid_min_.x(), nx_))];
}

bool SweptVolume::Occupied(const Eigen::Vector3d& p) const {
  const std::vector<std::size_t>& near = Near(p);
  return std::any_of(near.begin(), near.end(), [&](std::size_t i) { return Inside(swept_[i], p); });
}

bool SweptVolume::Vacated(const Eigen::Vector3d& p) const { return Occupied(p) && !OccupiedAtEnd(p); }

bool SweptVolume::OccupiedAtEnd(const Eigen::Vector3d& p) const {
  return std::any_of(now_.begin(), now_.end(), [&](const Box& b) { return Inside(b, p); });
}

}  // namespace dammloam::sim
