#pragma once
// Exact synthetic geometry for the map/registration suites: axis-aligned planes sampled on a
// grid, each point with its class and true normal (facing the inside of the room).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/geometry/point_class.hpp"

namespace dammloam::test {

struct LabelledCloud {
  std::vector<Eigen::Vector3d> points;
  std::vector<PointClass> labels;
  std::vector<Eigen::Vector3f> normals;

  void Add(const Eigen::Vector3d& p, PointClass c, const Eigen::Vector3f& n) {
    points.push_back(p);
    labels.push_back(c);
    normals.push_back(n);
  }
  LabelledCloud Transformed(const Eigen::Isometry3d& T) const {
    LabelledCloud out = *this;
    for (auto& p : out.points) p = T * p;
    for (auto& n : out.normals) n = T.linear().cast<float>() * n;
    return out;
  }
};

// Box [x0,x1] x [y0,y1] x [z0,z1] seen from inside: floor (ground), ceiling (roof), the two
// y walls always, the two x walls when `end_walls`. `offset` shifts the sampling grid.
inline LabelledCloud BoxRoom(double x0, double x1, double y0, double y1, double z0, double z1,
                             bool end_walls, double step, double offset = 0.0) {
  LabelledCloud c;
  for (double x = x0 + offset; x <= x1; x += step) {
    for (double y = y0 + offset; y <= y1; y += step) {
      c.Add({x, y, z0}, PointClass::Ground, {0, 0, 1});
      c.Add({x, y, z1}, PointClass::Roof, {0, 0, -1});
    }
    for (double z = z0 + offset; z <= z1; z += step) {
      c.Add({x, y0, z}, PointClass::Wall, {0, 1, 0});
      c.Add({x, y1, z}, PointClass::Wall, {0, -1, 0});
    }
  }
  if (end_walls) {
    for (double y = y0 + offset; y <= y1; y += step) {
      for (double z = z0 + offset; z <= z1; z += step) {
        c.Add({x0, y, z}, PointClass::Wall, {1, 0, 0});
        c.Add({x1, y, z}, PointClass::Wall, {-1, 0, 0});
      }
    }
  }
  return c;
}

inline Eigen::Isometry3d MakePose(double x, double y, double z, double roll, double pitch,
                                  double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

}  // namespace dammloam::test
