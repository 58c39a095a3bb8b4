#pragma once
#include <Eigen/Core>
#include <vector>

namespace dammloam::sim {

// A planar centreline made of straight lines and circular arcs, parameterised by arc length, so
// a vehicle at constant speed has s = speed * t. Heading is continuous across segments.
class Path {
 public:
  struct State {
    Eigen::Vector2d position;
    double heading = 0.0;  // rad, counter-clockwise from +x
  };

  explicit Path(State start = {Eigen::Vector2d::Zero(), 0.0}) : start_(start) {}

  Path& Line(double length);
  // Turns left for angle > 0, right for angle < 0.
  Path& Arc(double radius, double angle);

  double length() const { return total_length_; }
  // Outside [0, length()] the path extends straight along its end headings, unless `wrap`,
  // which repeats a closed path.
  State At(double s, bool wrap = false) const;
  // Signed curvature (1/radius, > 0 turning left) at arc length s; 0 outside [0, length()].
  double Curvature(double s) const;

 private:
  struct Segment {
    State start;
    double s_start = 0.0;
    double length = 0.0;
    double curvature = 0.0;  // 1/radius, signed; 0 for a line
  };
  State End() const;

  State start_;
  std::vector<Segment> segments_;
  double total_length_ = 0.0;
};

}  // namespace dammloam::sim
