#include "tools/simulate/path.hpp"

#include <algorithm>
#include <cmath>

namespace dammloam::sim {

namespace {
Path::State Advance(const Path::State& from, double curvature, double ds) {
  if (std::abs(curvature) < 1e-12) {
    return {from.position + ds * Eigen::Vector2d(std::cos(from.heading), std::sin(from.heading)),
            from.heading};
  }
  const double heading = from.heading + curvature * ds;
  const Eigen::Vector2d offset(std::sin(heading) - std::sin(from.heading),
                               -std::cos(heading) + std::cos(from.heading));
  return {from.position + offset / curvature, heading};
}
}  // namespace

Path::State Path::End() const {
  if (segments_.empty()) return start_;
  const Segment& last = segments_.back();
  return Advance(last.start, last.curvature, last.length);
}

Path& Path::Line(double length) {
  segments_.push_back({End(), total_length_, length, 0.0});
  total_length_ += length;
  return *this;
}

Path& Path::Arc(double radius, double angle) {
  const double length = radius * std::abs(angle);
  segments_.push_back({End(), total_length_, length, angle > 0 ? 1.0 / radius : -1.0 / radius});
  total_length_ += length;
  return *this;
}

Path::State Path::At(double s, bool wrap) const {
  if (segments_.empty()) return start_;
  if (wrap && total_length_ > 0.0) {
    s = std::fmod(s, total_length_);
    if (s < 0.0) s += total_length_;
  }
  // Beyond either end the path continues straight, so motion stays smooth at the start.
  if (s < 0.0) return Advance(start_, 0.0, s);
  if (s > total_length_) return Advance(End(), 0.0, s - total_length_);
  const auto it = std::upper_bound(segments_.begin(), segments_.end(), s,
                                   [](double v, const Segment& seg) { return v < seg.s_start; });
  const Segment& seg = *std::prev(it);
  return Advance(seg.start, seg.curvature, s - seg.s_start);
}

double Path::Curvature(double s) const {
  if (segments_.empty() || s < 0.0 || s > total_length_) return 0.0;
  const auto it = std::upper_bound(segments_.begin(), segments_.end(), s,
                                   [](double v, const Segment& seg) { return v < seg.s_start; });
  return std::prev(it)->curvature;
}

}  // namespace dammloam::sim
