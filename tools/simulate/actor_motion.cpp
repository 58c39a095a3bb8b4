#include "tools/simulate/actor_motion.hpp"
#include "tools/simulate/angles.hpp"

#include <algorithm>
#include <cmath>

namespace dammloam::sim {

namespace {


// Coinciding points would make a leg without a direction.
std::vector<Eigen::Vector2d> WithoutRepeats(const std::vector<Eigen::Vector2d>& points) {
  std::vector<Eigen::Vector2d> out;
  for (const Eigen::Vector2d& p : points) {
    if (out.empty() || (p - out.back()).norm() > 1e-6) out.push_back(p);
  }
  return out;
}

double Smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

}  // namespace

Route::Route(std::vector<Eigen::Vector2d> points, double speed, double start_time,
             std::vector<Stop> stops, bool closed)
    : points_(WithoutRepeats(points)), speed_(speed), start_time_(start_time), closed_(closed) {
  if (points_.empty()) points_.push_back(Eigen::Vector2d::Zero());
  if (closed_ && points_.size() > 1) points_.push_back(points_.front());
  cumulative_.push_back(0.0);
  for (std::size_t i = 1; i < points_.size(); ++i) {
    cumulative_.push_back(cumulative_.back() + (points_[i] - points_[i - 1]).norm());
  }
  if (points_.size() < 2 || !(speed_ > 0.0)) {
    closed_ = false;
    speed_ = 0.0;
  }
  std::sort(stops.begin(), stops.end(), [](const Stop& a, const Stop& b) { return a.at < b.at; });
  for (const Stop& stop : stops) {
    if (stop.at > 0.0 && stop.at < length() && stop.duration > 0.0) stops_.push_back(stop);
  }
}

Route::Route(const Eigen::Vector2d& position, double yaw) : standing_yaw_(yaw) {
  points_.push_back(position);
  cumulative_.push_back(0.0);
}

double Route::DistanceAt(double t) const {
  if (speed_ <= 0.0 || t <= start_time_) return 0.0;
  double walking = t - start_time_;  // time spent walking so far, stops taken off below
  for (const Stop& stop : stops_) {
    const double reach = stop.at / speed_;
    if (walking <= reach) break;
    walking = std::max(reach, walking - stop.duration);
    if (walking == reach) return stop.at;
  }
  const double s = walking * speed_;
  return closed_ ? s : std::min(s, length());
}

double Route::TimeAt(double s) const {
  if (speed_ <= 0.0) return start_time_;
  if (!closed_) s = std::clamp(s, 0.0, length());
  double t = start_time_ + s / speed_;
  for (const Stop& stop : stops_) {
    if (stop.at < s) t += stop.duration;
  }
  return t;
}

double Route::end_time() const { return closed_ ? kForever : TimeAt(length()); }

GroundPose Route::AtDistance(double s) const {
  if (points_.size() < 2) return {points_.front(), standing_yaw_};
  if (closed_) {
    s = std::fmod(s, length());
    if (s < 0.0) s += length();
  }
  s = std::clamp(s, 0.0, length());
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  const std::size_t i =
      std::min(static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cumulative_.begin(), 1)),
               points_.size() - 1);
  const Eigen::Vector2d leg = points_[i] - points_[i - 1];
  const double f = (s - cumulative_[i - 1]) / (cumulative_[i] - cumulative_[i - 1]);
  return {points_[i - 1] + f * leg, std::atan2(leg.y(), leg.x())};
}

GroundPose Swing::At(double t) const {
  const double opened = std::isfinite(open_time) ? Smoothstep((t - open_time) / duration) : 0.0;
  return {hinge, closed_yaw + opened * open_angle};
}

GroundPose Leader::At(double t) const {
  const Path& path = carrier->spec().path;
  const bool wrap = carrier->spec().closed;
  const double s = carrier->PathDistance(t);
  const Eigen::Vector2d from = path.At(s, wrap).position;
  auto gap = [&](double ahead) { return (path.At(s + ahead, wrap).position - from).norm(); };
  // A chord is never longer than its arc, so the gap is reached at `distance` or further on;
  // step until it is, then halve the last step (the path turns at most by a U-turn per step).
  double near = distance, far = distance;
  constexpr double kStep = 0.25, kFarthest = 50.0;
  while (gap(far) < distance && far < distance + kFarthest) {
    near = far;
    far += kStep;
  }
  for (int i = 0; i < 30 && far - near > 1e-4; ++i) {
    const double mid = 0.5 * (near + far);
    (gap(mid) < distance ? near : far) = mid;
  }
  const Path::State at = path.At(s + far, wrap);
  return {at.position, at.heading};
}

GroundPose Companion::At(double t) const {
  double s = 0.0;
  if (t < join_time) {
    s = carrier->PathDistance(join_time) - speed_before * (join_time - t);
  } else if (t > leave_time) {
    s = carrier->PathDistance(leave_time) + speed_after * (t - leave_time);
  } else {
    s = carrier->PathDistance(t);
  }
  const Path::State at = carrier->spec().path.At(s + along, carrier->spec().closed);
  return {at.position + lateral * LeftOf(at.heading), at.heading};
}

GroundPose PoseOf(const ActorMotion& motion, double t) {
  return std::visit([t](const auto& m) { return m.At(t); }, motion);
}

}  // namespace dammloam::sim
