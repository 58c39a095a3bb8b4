#pragma once
#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include "tools/simulate/primitives.hpp"

namespace dammloam::sim {

using Primitive = std::variant<Rectangle, Box, Cylinder, Sphere, CylinderX>;

// A static world of analytic primitives with a uniform 2-D grid over x-y, so a beam only tests
// the primitives in the cells it crosses. Primitives spanning many cells (long walls, floors)
// are tested for every beam instead, as is the optional heightfield ground.
class Scene {
 public:
  void Add(const Primitive& primitive) { primitives_.push_back(primitive); }
  void SetGround(const Heightfield& ground) { ground_ = ground; }
  const std::optional<Heightfield>& ground() const { return ground_; }
  const std::vector<Primitive>& primitives() const { return primitives_; }

  // Must be called after the last Add() and before Cast().
  void Build(double cell_size = 2.0);

  // Nearest surface along the ray with t_min < t < t_max, if any.
  std::optional<Hit> Cast(const Ray& ray, double t_min, double t_max) const;

 private:
  struct Cell {
    std::uint32_t begin = 0, end = 0;  // range in cell_items_
  };

  bool TestPrimitive(std::uint32_t index, const Ray& ray, double t_min, Hit& best) const;
  void WalkGrid(const Ray& ray, double t_min, Hit& best) const;

  std::vector<Primitive> primitives_;
  std::optional<Heightfield> ground_;
  std::vector<std::uint32_t> global_items_;  // tested for every ray
  std::vector<std::uint32_t> cell_items_;
  std::vector<Cell> cells_;
  Eigen::Vector2d grid_min_ = Eigen::Vector2d::Zero();
  double cell_size_ = 2.0;
  int nx_ = 0, ny_ = 0;
};

}  // namespace dammloam::sim
