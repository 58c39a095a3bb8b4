#include "core/odometry/compact_objects.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dammloam {

namespace {
constexpr float kEmpty = std::numeric_limits<float>::infinity();
bool Judged(PointClass c) { return c != PointClass::Ground && c != PointClass::Roof; }
float Elevation(const Eigen::Vector3d& p) {
  return static_cast<float>(std::atan2(p.z(), p.head<2>().norm()));
}
}  // namespace

bool CompactObjects::GroundHeight(const std::vector<Eigen::Vector3d>& upright,
                                  const std::vector<PointClass>& labels, float& ground) {
  const double reach_sq = config_.ground_reach * config_.ground_reach;
  ground_z_.clear();
  for (std::size_t i = 0; i < upright.size() && i < labels.size(); ++i) {
    if (labels[i] == PointClass::Ground && upright[i].head<2>().squaredNorm() <= reach_sq) {
      ground_z_.push_back(static_cast<float>(upright[i].z()));
    }
  }
  if (static_cast<int>(ground_z_.size()) < config_.min_ground_points) return false;
  auto middle = ground_z_.begin() + static_cast<std::ptrdiff_t>(ground_z_.size() / 2);
  std::nth_element(ground_z_.begin(), middle, ground_z_.end());
  ground = *middle;
  return true;
}

// One object: the occupied cells 8-connected to `start`, walked with an explicit stack.
void CompactObjects::Label(int start) {
  const int id = static_cast<int>(objects_.size());
  Object object{Eigen::Vector2f::Constant(kEmpty), Eigen::Vector2f::Constant(-kEmpty), kEmpty,
                -kEmpty, false, kEmpty, -kEmpty, kEmpty, -kEmpty, -kEmpty};
  stack_.assign(1, start);
  cells_[start].object = id;
  while (!stack_.empty()) {
    const int k = stack_.back();
    stack_.pop_back();
    const Eigen::Vector2f xy(static_cast<float>(k % side_), static_cast<float>(k / side_));
    object.lo = object.lo.cwiseMin(xy);
    object.hi = object.hi.cwiseMax(xy);
    object.z_min = std::min(object.z_min, cells_[k].z_min);
    object.z_max = std::max(object.z_max, cells_[k].z_max);
    const int x = k % side_, y = k / side_;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= side_ || ny >= side_) continue;
        Cell& n = cells_[ny * side_ + nx];
        if (n.z_min == kEmpty || n.object >= 0) continue;
        n.object = id;
        stack_.push_back(ny * side_ + nx);
      }
    }
  }
  objects_.push_back(object);
}

const std::vector<std::uint8_t>& CompactObjects::Find(const std::vector<Eigen::Vector3d>& points_sensor,
                                                      const std::vector<PointClass>& labels,
                                                      const std::vector<Eigen::Vector3f>& normals,
                                                      const Eigen::Vector3d& direction,
                                                      const Eigen::Matrix3d& R_world_sensor) {
  const int half = static_cast<int>(std::ceil(config_.max_range / config_.cell));
  if (side_ != 2 * half + 1) {
    side_ = 2 * half + 1;
    cells_.assign(static_cast<std::size_t>(side_) * side_, Cell{kEmpty, -kEmpty, -1});
    occupied_.clear();
  }
  for (int k : occupied_) cells_[k] = Cell{kEmpty, -kEmpty, -1};  // the last scan's, only
  occupied_.clear();
  objects_.clear();
  mask_.clear();
  upright_.resize(points_sensor.size());
  for (std::size_t i = 0; i < points_sensor.size(); ++i) upright_[i] = R_world_sensor * points_sensor[i];
  float ground = 0.0f;
  if (!GroundHeight(upright_, labels, ground)) return mask_;
  // The direction along the ground: a mostly vertical one has no bodies facing it.
  Eigen::Vector2d along = (R_world_sensor * direction).head<2>();
  if (along.norm() < 0.5) {
    mask_.assign(points_sensor.size(), 0);
    return mask_;
  }
  along.normalize();
  const Eigen::Vector2d across(-along.y(), along.x());

  const double range_sq = config_.max_range * config_.max_range;
  pixel_.assign(points_sensor.size(), -1);
  judged_.assign(points_sensor.size(), 0);
  for (std::size_t i = 0; i < points_sensor.size(); ++i) {
    if (i < labels.size() && !Judged(labels[i])) continue;
    judged_[i] = 1;
    if (i >= normals.size() ||
        std::abs(normals[i].cast<double>().dot(direction)) < config_.facing_cos) {
      continue;
    }
    const Eigen::Vector3d& p = upright_[i];
    if (p.head<2>().squaredNorm() > range_sq) continue;
    const int x = half + static_cast<int>(std::floor(p.x() / config_.cell));
    const int y = half + static_cast<int>(std::floor(p.y() / config_.cell));
    if (x < 0 || y < 0 || x >= side_ || y >= side_) continue;
    const int k = y * side_ + x;
    Cell& c = cells_[k];
    if (c.z_min == kEmpty) occupied_.push_back(k);
    c.z_min = std::min(c.z_min, static_cast<float>(p.z()));
    c.z_max = std::max(c.z_max, static_cast<float>(p.z()));
    pixel_[i] = k;
  }
  for (int k : occupied_) {
    if (cells_[k].object < 0) Label(k);
  }
  // Each object's facing points, along and across the direction, and how high they reach in
  // the view.
  float view_top = -kEmpty;
  for (const Eigen::Vector3d& p : points_sensor) view_top = std::max(view_top, Elevation(p));
  for (std::size_t i = 0; i < points_sensor.size(); ++i) {
    if (pixel_[i] < 0) continue;
    Object& o = objects_[cells_[pixel_[i]].object];
    o.elevation_max = std::max(o.elevation_max, Elevation(points_sensor[i]));
    const Eigen::Vector2d xy = upright_[i].head<2>();
    const float a = static_cast<float>(xy.dot(along)), c = static_cast<float>(xy.dot(across));
    o.along_min = std::min(o.along_min, a);
    o.along_max = std::max(o.along_max, a);
    o.across_min = std::min(o.across_min, c);
    o.across_max = std::max(o.across_max, c);
  }
  const float extent_cells = static_cast<float>(config_.max_extent / config_.cell);
  const float clipped = view_top - static_cast<float>(config_.top_margin_deg * M_PI / 180.0);
  for (Object& o : objects_) {
    // Cells are counted by index: the footprint spans (hi - lo + 1) cells each way.
    const float diagonal = (o.hi - o.lo + Eigen::Vector2f::Ones()).norm();
    // A surface that faces the direction is wider across it than deep along it; stray normals
    // on a wall that runs along the direction (at close range, where noise turns a few) are
    // the other way round.
    const bool faces = o.along_max - o.along_min <=
                       config_.body_depth + (o.across_max - o.across_min);
    o.compact = diagonal <= extent_cells && faces && o.elevation_max < clipped &&
                o.z_max - o.z_min >= config_.min_height &&
                o.z_min - ground <= config_.max_lift && o.z_max - ground <= config_.max_height;
  }
  mask_.assign(points_sensor.size(), 0);
  for (std::size_t i = 0; i < points_sensor.size(); ++i) {
    if (pixel_[i] >= 0) mask_[i] = objects_[cells_[pixel_[i]].object].compact ? 1 : 0;
  }
  MarkBodies(along, across, ground);
  return mask_;
}

void CompactObjects::MarkBodies(const Eigen::Vector2d& along, const Eigen::Vector2d& across,
                                float ground) {
  if (std::none_of(mask_.begin(), mask_.end(), [](std::uint8_t m) { return m != 0; })) return;
  const float depth = static_cast<float>(config_.body_depth);
  const float margin = static_cast<float>(config_.body_margin);
  const float top = ground + static_cast<float>(config_.max_height);
  const double range_sq = config_.max_range * config_.max_range;
  for (std::size_t i = 0; i < mask_.size(); ++i) {
    if (mask_[i] || !judged_[i]) continue;
    const Eigen::Vector3d& p = upright_[i];
    if (p.head<2>().squaredNorm() > range_sq || p.z() > top) continue;
    const float a = static_cast<float>(p.head<2>().dot(along));
    const float c = static_cast<float>(p.head<2>().dot(across));
    for (const Object& o : objects_) {
      if (!o.compact || o.along_min > o.along_max) continue;
      if (a >= o.along_min - depth && a <= o.along_max + depth && c >= o.across_min - margin &&
          c <= o.across_max + margin && p.z() <= o.z_max + margin) {
        mask_[i] = 1;
        break;
      }
    }
  }
}

namespace {
Eigen::Matrix3d Information(const std::vector<Eigen::Vector3f>& normals,
                            const std::vector<std::size_t>& indices) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i : indices) {
    if (i < normals.size()) H.noalias() += normals[i].cast<double>() * normals[i].cast<double>().transpose();
  }
  return H;
}
}  // namespace

Eigen::Vector3d WeakestDirection(const std::vector<Eigen::Vector3f>& normals,
                                 const std::vector<std::size_t>& indices) {
  return WeakestAxisOf(normals, indices).direction;
}

WeakestAxis WeakestAxisOf(const std::vector<Eigen::Vector3f>& normals,
                          const std::vector<std::size_t>& indices) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Information(normals, indices));
  const Eigen::Vector3d& lambda = solver.eigenvalues();  // ascending
  return {solver.eigenvectors().col(0), lambda(2) > 0.0 ? lambda(0) / lambda(2) : 1.0};
}

std::vector<std::uint8_t> MapLater(const std::vector<PointClass>& labels,
                                   const std::vector<Eigen::Vector3f>& normals,
                                   const WeakestAxis& weakest,
                                   const std::vector<std::uint8_t>& object_mask,
                                   const CompactObjectsConfig& config) {
  std::vector<std::uint8_t> later(labels.size(), 0);
  for (std::size_t i = 0; i < object_mask.size() && i < later.size(); ++i) later[i] = object_mask[i];
  if (!(weakest.share < config.weak_axis_ratio)) return later;
  const Eigen::Vector3f d = weakest.direction.cast<float>();
  for (std::size_t i = 0; i < later.size(); ++i) {
    if (!Judged(labels[i])) continue;
    const bool faces = i < normals.size() && std::abs(normals[i].dot(d)) >= config.facing_cos;
    if (faces || labels[i] == PointClass::Edge) later[i] = 1;
  }
  return later;
}

bool ObjectsWitnessTheWeakAxis(const std::vector<Eigen::Vector3f>& normals,
                               const std::vector<std::size_t>& indices,
                               const std::vector<std::uint8_t>& object_mask,
                               const CompactObjectsConfig& config) {
  Eigen::Matrix3d rest = Eigen::Matrix3d::Zero(), objects = Eigen::Matrix3d::Zero();
  bool any = false;
  for (std::size_t i : indices) {
    if (i >= normals.size()) continue;
    const Eigen::Vector3d n = normals[i].cast<double>();
    if (i < object_mask.size() && object_mask[i]) {
      objects.noalias() += n * n.transpose();
      any = true;
    } else {
      rest.noalias() += n * n.transpose();
    }
  }
  if (!any) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(rest);
  const Eigen::Vector3d& lambda = solver.eigenvalues();  // ascending
  const Eigen::Vector3d weakest = solver.eigenvectors().col(0);
  if (!(lambda(0) < config.weak_axis_ratio * lambda(2))) return false;
  return weakest.dot(objects * weakest) >= config.witness_share * std::max(lambda(0), 1e-9);
}

}  // namespace dammloam
