#include "tools/simulate/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dammloam::sim {

namespace {

Bounds2d BoundsOfPoints(const std::vector<Eigen::Vector3d>& points) {
  Bounds2d b{points.front().head<2>(), points.front().head<2>()};
  for (const auto& p : points) {
    b.min = b.min.cwiseMin(p.head<2>());
    b.max = b.max.cwiseMax(p.head<2>());
  }
  return b;
}

bool Accept(double t, double t_min, const Hit& best) { return t > t_min && t < best.t; }

}  // namespace

bool Rectangle::Intersect(const Ray& ray, double t_min, Hit& best) const {
  const double denom = normal.dot(ray.dir);
  if (std::abs(denom) < 1e-12) return false;  // beam parallel to the plane
  const double t = normal.dot(center - ray.origin) / denom;
  if (!Accept(t, t_min, best)) return false;
  const Eigen::Vector3d local = ray.origin + t * ray.dir - center;
  if (std::abs(axis_u.dot(local)) > half_u || std::abs(axis_v.dot(local)) > half_v) return false;
  best = Hit{t, normal, reflectivity};
  return true;
}

Bounds2d Rectangle::bounds() const {
  const Eigen::Vector3d u = half_u * axis_u, v = half_v * axis_v;
  return BoundsOfPoints({center + u + v, center + u - v, center - u + v, center - u - v});
}

bool Box::Intersect(const Ray& ray, double t_min, Hit& best) const {
  // Slab test in the box frame; the entry slab gives the face normal.
  const Eigen::Vector3d o = rotation.transpose() * (ray.origin - center);
  const Eigen::Vector3d d = rotation.transpose() * ray.dir;
  double t_enter = -std::numeric_limits<double>::infinity();
  double t_exit = std::numeric_limits<double>::infinity();
  int enter_axis = 0;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-15) {
      if (std::abs(o[i]) > half_size[i]) return false;
      continue;
    }
    double t0 = (-half_size[i] - o[i]) / d[i];
    double t1 = (half_size[i] - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_enter) {
      t_enter = t0;
      enter_axis = i;
    }
    t_exit = std::min(t_exit, t1);
    if (t_enter > t_exit) return false;
  }
  if (!Accept(t_enter, t_min, best)) return false;  // also rejects rays starting inside
  best = Hit{t_enter, rotation.col(enter_axis), reflectivity};
  return true;
}

Bounds2d Box::bounds() const {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d s((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    corners.push_back(center + rotation * s.cwiseProduct(half_size));
  }
  return BoundsOfPoints(corners);
}

bool Cylinder::Intersect(const Ray& ray, double t_min, Hit& best) const {
  bool hit = false;
  // Side: |o_xy + t d_xy - c|^2 = r^2.
  const Eigen::Vector2d o = ray.origin.head<2>() - center;
  const Eigen::Vector2d d = ray.dir.head<2>();
  const double a = d.squaredNorm();
  if (a > 1e-18) {
    const double half_b = o.dot(d);
    const double c = o.squaredNorm() - radius * radius;
    const double disc = half_b * half_b - a * c;
    if (disc >= 0.0) {
      const double t = (-half_b - std::sqrt(disc)) / a;  // outer surface only
      const double z = ray.origin.z() + t * ray.dir.z();
      if (z >= z_min && z <= z_max && Accept(t, t_min, best)) {
        const Eigen::Vector2d n = (o + t * d) / radius;
        best = Hit{t, Eigen::Vector3d(n.x(), n.y(), 0.0), reflectivity};
        hit = true;
      }
    }
  }
  // Top cap, seen from above.
  if (ray.dir.z() < -1e-15) {
    const double t = (z_max - ray.origin.z()) / ray.dir.z();
    if (Accept(t, t_min, best) && (o + t * d).squaredNorm() <= radius * radius) {
      best = Hit{t, Eigen::Vector3d::UnitZ(), reflectivity};
      hit = true;
    }
  }
  return hit;
}

Bounds2d Cylinder::bounds() const {
  return {center.array() - radius, center.array() + radius};
}

bool CylinderX::Intersect(const Ray& ray, double t_min, Hit& best) const {
  // |o_yz + t d_yz - c|^2 = r^2; the near root is the outer surface, the far one the inner.
  const Eigen::Vector2d o(ray.origin.y() - center.x(), ray.origin.z() - center.y());
  const Eigen::Vector2d d(ray.dir.y(), ray.dir.z());
  const double a = d.squaredNorm();
  if (a < 1e-18) return false;  // along the axis
  const double half_b = o.dot(d);
  const double c = o.squaredNorm() - radius * radius;
  const double disc = half_b * half_b - a * c;
  if (disc < 0.0) return false;
  const double root = std::sqrt(disc);
  const double t = inside ? (-half_b + root) / a : (-half_b - root) / a;
  if (!Accept(t, t_min, best)) return false;
  const Eigen::Vector3d p = ray.origin + t * ray.dir;
  if (p.x() < x_min || p.x() > x_max || p.z() < z_min) return false;
  const Eigen::Vector2d n = (o + t * d) / radius;
  best = Hit{t, Eigen::Vector3d(0.0, n.x(), n.y()), reflectivity};
  return true;
}

Bounds2d CylinderX::bounds() const {
  return {Eigen::Vector2d(x_min, center.x() - radius), Eigen::Vector2d(x_max, center.x() + radius)};
}

bool Sphere::Intersect(const Ray& ray, double t_min, Hit& best) const {
  const Eigen::Vector3d o = ray.origin - center;
  const double half_b = o.dot(ray.dir);
  const double c = o.squaredNorm() - radius * radius;
  const double disc = half_b * half_b - c;
  if (disc < 0.0) return false;
  const double t = -half_b - std::sqrt(disc);
  if (!Accept(t, t_min, best)) return false;
  best = Hit{t, (o + t * ray.dir) / radius, reflectivity};
  return true;
}

Bounds2d Sphere::bounds() const {
  return {center.head<2>().array() - radius, center.head<2>().array() + radius};
}

Heightfield::Heightfield(double base, std::vector<Ripple> ripples, float reflectivity)
    : base_(base), ripples_(std::move(ripples)), reflectivity_(reflectivity) {
  for (const auto& r : ripples_) {
    max_amplitude_ += std::abs(r.amplitude);
  }
}

double Heightfield::Height(double x, double y) const {
  double z = base_;
  for (const auto& r : ripples_) z += r.amplitude * std::sin(r.wave.x() * x + r.wave.y() * y + r.phase);
  return z;
}

Eigen::Vector2d Heightfield::Gradient(double x, double y) const {
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  for (const auto& r : ripples_) {
    g += r.amplitude * std::cos(r.wave.x() * x + r.wave.y() * y + r.phase) * r.wave;
  }
  return g;
}

Eigen::Vector3d Heightfield::Normal(double x, double y) const {
  const Eigen::Vector2d g = Gradient(x, y);
  return Eigen::Vector3d(-g.x(), -g.y(), 1.0).normalized();
}

bool Heightfield::Intersect(const Ray& ray, double t_min, Hit& best) const {
  // f(t) = height of the ray above the ground. Only the slab |z - base| <= max_amplitude_ can
  // hold a crossing. Above ground, |f'| <= |d_z| + sum |a_i k_i . d_xy| bounds how fast f drops,
  // so stepping by f / that bound never jumps over the first crossing.
  const Eigen::Vector3d& o = ray.origin;
  const Eigen::Vector3d& d = ray.dir;
  auto f = [&](double t) { return o.z() + t * d.z() - Height(o.x() + t * d.x(), o.y() + t * d.y()); };
  const double top = base_ + max_amplitude_, bottom = base_ - max_amplitude_;
  double t_lo = t_min, t_hi = best.t;
  if (std::abs(d.z()) > 1e-15) {
    const double t_top = (top - o.z()) / d.z(), t_bottom = (bottom - o.z()) / d.z();
    t_lo = std::max(t_lo, std::min(t_top, t_bottom));
    t_hi = std::min(t_hi, std::max(t_top, t_bottom));
  } else if (o.z() > top || o.z() < bottom) {
    return false;
  }
  if (!std::isfinite(t_hi)) t_hi = t_lo + 1e4;
  if (t_lo >= t_hi) return false;
  double t = t_lo;
  double ft = f(t);
  if (ft <= 0.0) return false;  // starts below ground: not a visible surface
  // How fast the ground can rise along this ray: each ripple only by its slope along d_xy.
  double drop_rate = std::abs(d.z());
  for (const auto& r : ripples_) drop_rate += std::abs(r.amplitude * r.wave.dot(d.head<2>()));
  drop_rate = std::max(drop_rate, 1e-9);
  // Safe steps shrink as the ray nears the ground. Below a 2 cm step the march strides on (a
  // ridge that would dip into the ray and out again within 2 cm is ignored), so it soon lands
  // below ground, and regula falsi on that last step pins the crossing down.
  constexpr double kMinStep = 0.02;
  double t_prev = t, f_prev = ft;
  while (ft > 0.0) {
    if (t >= t_hi) return false;
    t_prev = t;
    f_prev = ft;
    t = std::min(t + std::max(ft / drop_rate, kMinStep), t_hi);
    ft = f(t);
  }
  // Illinois variant of regula falsi on [a, b] with f(a) > 0 >= f(b).
  double a = t_prev, fa = f_prev, b = t, fb = ft;
  int side = 0;
  for (int i = 0; i < 40; ++i) {
    const double m = b - fb * (b - a) / (fb - fa);
    const double fm = f(m);
    if (std::abs(fm) < 1e-12 || b - a < 1e-12) {
      a = b = m;
      break;
    }
    if (fm > 0.0) {
      a = m;
      fa = fm;
      if (side == 1) fb *= 0.5;
      side = 1;
    } else {
      b = m;
      fb = fm;
      if (side == -1) fa *= 0.5;
      side = -1;
    }
  }
  t = 0.5 * (a + b);
  if (!Accept(t, t_min, best) || t > t_hi) return false;
  const Eigen::Vector3d p = o + t * d;
  best = Hit{t, Normal(p.x(), p.y()), reflectivity_};
  return true;
}

}  // namespace dammloam::sim
