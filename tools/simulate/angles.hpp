#pragma once
#include <Eigen/Core>
#include <cmath>
#include <numbers>

// Angle constants and the planar left-hand direction, shared by the simulator's files (each
// once had its own copy, which a unity build cannot hold together).
namespace dammloam::sim {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDegToRad = kPi / 180.0;

// Unit vector pointing left of a heading (rad, counter-clockwise from +x).
inline Eigen::Vector2d LeftOf(double heading) { return {-std::sin(heading), std::cos(heading)}; }

}  // namespace dammloam::sim
