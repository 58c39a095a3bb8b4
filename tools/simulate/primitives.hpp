#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

// Analytic surfaces a simulated beam can hit. Each Intersect() looks for the first hit with
// t_min < t < best.t along the ray and, if it finds one, overwrites `best` and returns true, so
// a caller keeps the nearest hit by passing the same Hit to every primitive.
namespace dammloam::sim {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d dir;  // unit length
};

struct Hit {
  double t = 0.0;                 // distance along the ray, metres
  Eigen::Vector3d normal{0, 0, 1};  // unit, world frame (sign not meaningful)
  float reflectivity = 0.0f;
};

// 2-D bounds in the ground plane, used to place primitives in the scene grid.
struct Bounds2d {
  Eigen::Vector2d min;
  Eigen::Vector2d max;
};

// Finite rectangle: centre, unit normal and two in-plane unit axes with half extents.
struct Rectangle {
  Eigen::Vector3d center;
  Eigen::Vector3d normal;
  Eigen::Vector3d axis_u;
  Eigen::Vector3d axis_v;
  double half_u = 1.0;
  double half_v = 1.0;
  float reflectivity = 0.5f;

  bool Intersect(const Ray& ray, double t_min, Hit& best) const;
  Bounds2d bounds() const;
};

// Box with half sizes along its own axes; rotation = world_from_box (identity: axis-aligned).
struct Box {
  Eigen::Vector3d center;
  Eigen::Vector3d half_size;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  float reflectivity = 0.5f;

  bool Intersect(const Ray& ray, double t_min, Hit& best) const;
  Bounds2d bounds() const;
};

// Vertical (z-axis) cylinder with a closed top, e.g. a tree trunk or a pole.
struct Cylinder {
  Eigen::Vector2d center;
  double radius = 0.2;
  double z_min = 0.0;
  double z_max = 3.0;
  float reflectivity = 0.4f;

  bool Intersect(const Ray& ray, double t_min, Hit& best) const;
  Bounds2d bounds() const;
};

// Cylinder lying along x: axis (y, z) = center, x in [x_min, x_max], open ends. `inside`: the
// inner surface (a tunnel seen from within; only the part with z >= z_min, e.g. above a flat
// floor), else the outer one (a pipe).
struct CylinderX {
  Eigen::Vector2d center;  // (y, z) of the axis
  double radius = 1.0;
  double x_min = 0.0;
  double x_max = 10.0;
  bool inside = false;
  double z_min = -1e9;
  float reflectivity = 0.5f;

  bool Intersect(const Ray& ray, double t_min, Hit& best) const;
  Bounds2d bounds() const;
};

struct Sphere {
  Eigen::Vector3d center;
  double radius = 1.0;
  float reflectivity = 0.3f;

  bool Intersect(const Ray& ray, double t_min, Hit& best) const;
  Bounds2d bounds() const;
};

// One sinusoidal ripple of the ground: amplitude * sin(wave . (x, y) + phase).
struct Ripple {
  double amplitude = 0.0;
  Eigen::Vector2d wave = Eigen::Vector2d::Zero();  // rad per metre
  double phase = 0.0;
};

// Smooth uneven ground z = base + sum of ripples, unbounded in x and y. The bounds on its
// amplitude and on each ripple's slope let the ray marcher step safely towards a crossing.
class Heightfield {
 public:
  Heightfield() = default;
  Heightfield(double base, std::vector<Ripple> ripples, float reflectivity = 0.25f);

  double Height(double x, double y) const;
  Eigen::Vector2d Gradient(double x, double y) const;
  Eigen::Vector3d Normal(double x, double y) const;
  bool Intersect(const Ray& ray, double t_min, Hit& best) const;

 private:
  double base_ = 0.0;
  std::vector<Ripple> ripples_;
  float reflectivity_ = 0.25f;
  double max_amplitude_ = 0.0;  // |Height - base| never exceeds this
};

}  // namespace dammloam::sim
