#pragma once
#include <Eigen/Core>

#include "core/geometry/point_class.hpp"

namespace dammloam {

// One map point, world frame. The normal is zero where the feature stage had none.
struct MapPoint {
  Eigen::Vector3d position;
  Eigen::Vector3f normal;
  PointClass label;
};

}  // namespace dammloam
