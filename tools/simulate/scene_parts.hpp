#pragma once
#include <Eigen/Geometry>

#include "tools/simulate/primitives.hpp"

// Axis-aligned building blocks the scene builders share (scenes.cpp, drift_scenes.cpp).
namespace dammloam::sim {

// Reflectivities: distinct per material so intensity images carry some texture.
inline constexpr float kFloor = 0.3f, kCeiling = 0.6f, kWall = 0.5f, kDoor = 0.2f, kPillar = 0.7f;
inline constexpr float kFacade = 0.55f, kTrunk = 0.35f, kCrown = 0.15f, kPole = 0.8f;

inline Rectangle HorizontalRect(double x0, double x1, double y0, double y1, double z, float refl) {
  return {{0.5 * (x0 + x1), 0.5 * (y0 + y1), z}, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
          Eigen::Vector3d::UnitY(), 0.5 * (x1 - x0), 0.5 * (y1 - y0), refl};
}

// Wall in a plane y = const, spanning x0..x1 and z0..z1.
inline Rectangle WallAlongX(double x0, double x1, double y, double z0, double z1, float refl) {
  return {{0.5 * (x0 + x1), y, 0.5 * (z0 + z1)}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(),
          Eigen::Vector3d::UnitZ(), 0.5 * (x1 - x0), 0.5 * (z1 - z0), refl};
}

// Wall in a plane x = const, spanning y0..y1 and z0..z1.
inline Rectangle WallAlongY(double y0, double y1, double x, double z0, double z1, float refl) {
  return {{x, 0.5 * (y0 + y1), 0.5 * (z0 + z1)}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
          Eigen::Vector3d::UnitZ(), 0.5 * (y1 - y0), 0.5 * (z1 - z0), refl};
}

inline Box AxisBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max, float refl) {
  return {0.5 * (min + max), 0.5 * (max - min), Eigen::Matrix3d::Identity(), refl};
}

}  // namespace dammloam::sim
