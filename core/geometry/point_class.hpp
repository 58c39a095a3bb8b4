#pragma once
#include <array>
#include <cstdint>
#include <string_view>

namespace dammloam {

// The five geometric classes of the paper (Sec. III-A.3), which the classifier gives, and
// Moving: a point on something that moves (core/odometry/moving_points.hpp), which the odometry
// gives in place of the geometric class once it has left the point out of registration and map.
// Values are part of the wire and file formats (PCD label field, LabelledCloud topic): never
// renumber.
enum class PointClass : std::uint8_t {
  Unknown = 0,
  Ground = 1,
  Roof = 2,
  Wall = 3,
  Edge = 4,
  Moving = 5
};

inline constexpr std::size_t kNumGeometricClasses = 5;  // Unknown .. Edge
inline constexpr std::size_t kNumPointClasses = 6;

using ClassCounts = std::array<std::uint32_t, kNumPointClasses>;

constexpr std::size_t Index(PointClass c) { return static_cast<std::size_t>(c); }

// Ground, roof and wall use point-to-plane residuals; edge and unknown use point-to-point.
constexpr bool IsPlanar(PointClass c) {
  return c == PointClass::Ground || c == PointClass::Roof || c == PointClass::Wall;
}

constexpr std::string_view Name(PointClass c) {
  switch (c) {
    case PointClass::Ground: return "ground";
    case PointClass::Roof: return "roof";
    case PointClass::Wall: return "wall";
    case PointClass::Edge: return "edge";
    case PointClass::Moving: return "moving";
    case PointClass::Unknown: break;
  }
  return "unknown";
}

}  // namespace dammloam
