#include "tools/simulate/placement_space.hpp"

#include <algorithm>
#include <cmath>

namespace dammloam::sim {

namespace {

constexpr double kOutlineCell = 4.0;  // metres, grid of static outlines
// Between samples the gap to the sensor is refined where it is this small (metres): sensor and
// actor together move less than this in a sample step.
constexpr double kRefineBelow = 2.0;
constexpr double kRefineStep = 0.01;

double PointToBox(const Eigen::Vector3d& p, const Box& box) {
  const Eigen::Vector3d local = box.rotation.transpose() * (p - box.center);
  return (local.cwiseAbs() - box.half_size).cwiseMax(0.0).norm();
}

int CellIndex(double value, double origin, int count) {
  return std::clamp(static_cast<int>(std::floor((value - origin) / kOutlineCell)), 0, count - 1);
}

}  // namespace

PlacementSpace::PlacementSpace(const World& world, const Trajectory& trajectory, double duration)
    : duration_(duration),
      trajectory_(&trajectory),
      ground_(world.scene.ground()),
      corridor_(world.layout.corridor) {
  const int samples = static_cast<int>(std::ceil(duration_ / kPlacementStep)) + 1;
  for (int k = 0; k < samples; ++k) sensor_.push_back(SensorAt(k * kPlacementStep));
  AddOutlines(world.scene);
}

Eigen::Vector3d PlacementSpace::SensorAt(double t) const { return trajectory_->Pose(t).translation(); }

void PlacementSpace::AddOutlines(const Scene& scene) {
  for (const Primitive& primitive : scene.primitives()) {
    Outline o;
    if (const auto* r = std::get_if<Rectangle>(&primitive)) {
      const double dz = std::abs(r->axis_u.z()) * r->half_u + std::abs(r->axis_v.z()) * r->half_v;
      if (std::abs(r->normal.z()) > 0.1) continue;  // floors and ceilings
      o.z_min = r->center.z() - dz;
      o.z_max = r->center.z() + dz;
      const bool u_level = std::abs(r->axis_u.z()) < std::abs(r->axis_v.z());
      const Eigen::Vector2d along = (u_level ? r->axis_u : r->axis_v).head<2>();
      const double half = (u_level ? r->half_u : r->half_v) * along.norm();
      o.center = r->center.head<2>();
      o.axes.col(0) = along.normalized();
      o.axes.col(1) = Eigen::Vector2d(-o.axes(1, 0), o.axes(0, 0));
      o.half = Eigen::Vector2d(half, 0.01);
    } else if (const auto* b = std::get_if<Box>(&primitive)) {
      const double dz = b->rotation.row(2).cwiseAbs().dot(b->half_size);
      o.z_min = b->center.z() - dz;
      o.z_max = b->center.z() + dz;
      if (std::abs(b->rotation(2, 2)) > 0.999) {
        o.center = b->center.head<2>();
        o.axes = b->rotation.topLeftCorner<2, 2>();
        o.axes.col(0).normalize();
        o.axes.col(1).normalize();
        o.half = b->half_size.head<2>();
      } else {
        const Bounds2d bounds = b->bounds();
        o.center = 0.5 * (bounds.min + bounds.max);
        o.half = 0.5 * (bounds.max - bounds.min);
      }
    } else if (const auto* c = std::get_if<Cylinder>(&primitive)) {
      o.center = c->center;
      o.radius = c->radius;
      o.z_min = c->z_min;
      o.z_max = c->z_max;
    } else if (const auto* s = std::get_if<Sphere>(&primitive)) {
      o.center = s->center.head<2>();
      o.radius = s->radius;
      o.z_min = s->center.z() - s->radius;
      o.z_max = s->center.z() + s->radius;
      o.sphere = *s;
    } else if (const auto* x = std::get_if<CylinderX>(&primitive)) {
      if (x->inside) continue;  // a tunnel's wall: its floor is the corridor
      o.center = Eigen::Vector2d(0.5 * (x->x_min + x->x_max), x->center.x());
      o.half = Eigen::Vector2d(0.5 * (x->x_max - x->x_min), x->radius);
      o.z_min = x->center.y() - x->radius;
      o.z_max = x->center.y() + x->radius;
    }
    outlines_.push_back(o);
  }
  if (outlines_.empty()) return;
  auto extent = [](const Outline& o) -> Eigen::Vector2d {
    return o.radius > 0.0 ? Eigen::Vector2d::Constant(o.radius) : Eigen::Vector2d(o.axes.cwiseAbs() * o.half);
  };
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(kForever), hi = -lo;
  for (const Outline& o : outlines_) {
    lo = lo.cwiseMin(o.center - extent(o));
    hi = hi.cwiseMax(o.center + extent(o));
  }
  grid_min_ = lo;
  nx_ = static_cast<int>((hi.x() - lo.x()) / kOutlineCell) + 1;
  ny_ = static_cast<int>((hi.y() - lo.y()) / kOutlineCell) + 1;
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  for (std::size_t i = 0; i < outlines_.size(); ++i) {
    const Eigen::Vector2d a = outlines_[i].center - extent(outlines_[i]);
    const Eigen::Vector2d b = outlines_[i].center + extent(outlines_[i]);
    for (int y = CellIndex(a.y(), lo.y(), ny_); y <= CellIndex(b.y(), lo.y(), ny_); ++y) {
      for (int x = CellIndex(a.x(), lo.x(), nx_); x <= CellIndex(b.x(), lo.x(), nx_); ++x) {
        cells_[static_cast<std::size_t>(y) * nx_ + x].push_back(i);
      }
    }
  }
}

std::vector<std::size_t> PlacementSpace::OutlinesNear(const Eigen::Vector2d& min,
                                                      const Eigen::Vector2d& max) const {
  std::vector<std::size_t> out;
  if (cells_.empty()) return out;
  for (int y = CellIndex(min.y(), grid_min_.y(), ny_); y <= CellIndex(max.y(), grid_min_.y(), ny_); ++y) {
    for (int x = CellIndex(min.x(), grid_min_.x(), nx_); x <= CellIndex(max.x(), grid_min_.x(), nx_); ++x) {
      const auto& cell = cells_[static_cast<std::size_t>(y) * nx_ + x];
      out.insert(out.end(), cell.begin(), cell.end());
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::optional<PlacementSpace::Outline> PlacementSpace::Slice(const Outline& o, double z_min, double z_max) {
  if (o.z_max <= z_min || o.z_min >= z_max) return std::nullopt;
  if (!o.sphere) return o;
  // The sphere's widest circle within the heights.
  const double dz = std::max({0.0, z_min - o.sphere->center.z(), o.sphere->center.z() - z_max});
  Outline slice = o;
  slice.radius = std::sqrt(std::max(0.0, o.sphere->radius * o.sphere->radius - dz * dz));
  return slice;
}

bool PlacementSpace::Overlaps(const Outline& a, const Outline& b) {
  if (a.radius > 0.0 && b.radius > 0.0) return (a.center - b.center).norm() < a.radius + b.radius;
  if (a.radius > 0.0 || b.radius > 0.0) {
    const Outline& circle = a.radius > 0.0 ? a : b;
    const Outline& rect = a.radius > 0.0 ? b : a;
    const Eigen::Vector2d local = rect.axes.transpose() * (circle.center - rect.center);
    return (local.cwiseAbs() - rect.half).cwiseMax(0.0).norm() < circle.radius;
  }
  // Separating axes of two rectangles: their four edge directions.
  const Eigen::Vector2d between = b.center - a.center;
  for (const Eigen::Matrix2d* axes : {&a.axes, &b.axes}) {
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d n = axes->col(i);
      const double ra = (a.axes.transpose() * n).cwiseAbs().dot(a.half);
      const double rb = (b.axes.transpose() * n).cwiseAbs().dot(b.half);
      if (std::abs(n.dot(between)) > ra + rb) return false;
    }
  }
  return true;
}

PlacementSpace::Outline PlacementSpace::OutlineOf(const Box& body, double margin) {
  Outline o;
  o.center = body.center.head<2>();
  o.axes = body.rotation.topLeftCorner<2, 2>();
  o.half = body.half_size.head<2>() + Eigen::Vector2d::Constant(margin);
  return o;
}

ActorTrack PlacementSpace::Track(const Actor& actor) const {
  ActorTrack track;
  track.bodies.resize(sensor_.size());
  for (std::size_t k = 0; k < sensor_.size(); ++k) {
    const double t = static_cast<double>(k) * kPlacementStep;
    if (actor.PresentAt(t)) track.bodies[k] = BodyInWorld(actor, ActorFrame(actor, t, ground_));
  }
  return track;
}

bool PlacementSpace::ClearOfScene(const Box& body, double margin) const {
  const Outline outline = OutlineOf(body, margin);
  const Eigen::Vector2d extent = outline.axes.cwiseAbs() * outline.half;
  if (corridor_) {
    const Eigen::Vector2d inner = body.rotation.topLeftCorner<2, 2>().cwiseAbs() * body.half_size.head<2>();
    if (((body.center.head<2>() - inner) - corridor_->min).minCoeff() < 0.0 ||
        (corridor_->max - (body.center.head<2>() + inner)).minCoeff() < 0.0) {
      return false;
    }
  }
  // Feet stand on the ground, which the outlines do not include; from 10 cm up to the top.
  const double z_min = body.center.z() - body.half_size.z() + 0.1, z_max = body.center.z() + body.half_size.z();
  for (const std::size_t i : OutlinesNear(outline.center - extent, outline.center + extent)) {
    const std::optional<Outline> obstacle = Slice(outlines_[i], z_min, z_max);
    if (obstacle && (!obstacle->sphere || obstacle->radius > 0.0) && Overlaps(outline, *obstacle)) return false;
  }
  return true;
}

bool PlacementSpace::ClearOfScene(const ActorTrack& track, double margin) const {
  const Box* checked = nullptr;
  for (const std::optional<Box>& body : track.bodies) {
    if (!body) continue;
    // A body that has hardly moved since the last check would pass or fail the same way.
    if (checked && (body->center - checked->center).norm() < 0.05 &&
        body->rotation.isApprox(checked->rotation, 1e-3)) {
      continue;
    }
    if (!ClearOfScene(*body, margin)) return false;
    checked = &*body;
  }
  return true;
}

double PlacementSpace::SensorGap(const Actor& actor, const ActorTrack& track) const {
  double gap = kForever;
  for (std::size_t k = 0; k < track.bodies.size(); ++k) {
    if (!track.bodies[k]) continue;
    const double d = PointToBox(sensor_[k], *track.bodies[k]);
    gap = std::min(gap, d);
    if (d >= kRefineBelow) continue;
    const double t_k = static_cast<double>(k) * kPlacementStep;
    for (double t = t_k - kPlacementStep; t < t_k + kPlacementStep; t += kRefineStep) {
      if (t < 0.0 || t > duration_ || !actor.PresentAt(t)) continue;
      gap = std::min(gap, PointToBox(SensorAt(t), BodyInWorld(actor, ActorFrame(actor, t, ground_))));
    }
  }
  return gap;
}

double PlacementSpace::ClosestPass(const ActorTrack& track) const {
  double closest = kForever;
  for (std::size_t k = 0; k < track.bodies.size(); ++k) {
    if (track.bodies[k]) {
      closest = std::min(closest, (track.bodies[k]->center - sensor_[k]).head<2>().norm());
    }
  }
  return closest;
}

bool PlacementSpace::ClearOfActors(const ActorTrack& track) const {
  for (const ActorTrack& other : tracks_) {
    for (std::size_t k = 0; k < track.bodies.size(); ++k) {
      if (!track.bodies[k] || !other.bodies[k]) continue;
      const Box& a = *track.bodies[k];
      const Box& b = *other.bodies[k];
      const double reach = a.half_size.head<2>().norm() + b.half_size.head<2>().norm() + 0.1;
      if ((a.center - b.center).head<2>().norm() > reach) continue;
      if (Overlaps(OutlineOf(a, 0.05), OutlineOf(b, 0.05))) return false;
    }
  }
  return true;
}

double PlacementSpace::PopDistance(const Actor& actor) const {
  double nearest = kForever;
  for (const double t : {actor.appear, actor.vanish}) {
    if (!(t >= 0.0 && t <= duration_)) continue;
    const Box body = BodyInWorld(actor, ActorFrame(actor, t, ground_));
    nearest = std::min(nearest, (body.center - SensorAt(t)).head<2>().norm());
  }
  return nearest;
}

void PlacementSpace::Accept(Actor actor, ActorTrack track) {
  actors_.push_back(std::move(actor));
  tracks_.push_back(std::move(track));
}

void PlacementSpace::Truncate(std::size_t count) {
  actors_.resize(std::min(count, actors_.size()));
  tracks_.resize(actors_.size());
}

}  // namespace dammloam::sim
