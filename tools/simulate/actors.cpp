#include "tools/simulate/actors.hpp"

#include <algorithm>
#include <cmath>

namespace dammloam::sim {

namespace {

constexpr double kHeadRadius = 0.11;
constexpr double kDoorThickness = 0.04;

Box LocalBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half_size, float reflectivity) {
  return {center, half_size, Eigen::Matrix3d::Identity(), reflectivity};
}

ActorPart ToWorld(const ActorPart& part, const Eigen::Isometry3d& frame) {
  if (const auto* box = std::get_if<Box>(&part)) {
    return Box{frame * box->center, box->half_size, frame.linear() * box->rotation, box->reflectivity};
  }
  const auto& sphere = std::get<Sphere>(part);
  return Sphere{frame * sphere.center, sphere.radius, sphere.reflectivity};
}

// Farthest any point of the body gets from the origin's vertical, whatever the yaw.
double HorizontalReach(const Box& body) {
  return body.center.head<2>().norm() + body.half_size.head<2>().norm();
}

// Samples per scan for an actor's reach: fine enough that its origin never strays between two
// of them by more than the margin added (10 m/s * 5 ms).
constexpr double kReachStep = 0.01;

}  // namespace

Actor MakePedestrian(ActorMotion motion, double height, float reflectivity, ActorRole role) {
  Actor a;
  a.kind = ActorKind::Pedestrian;
  a.role = role;
  a.motion = std::move(motion);
  const double shoulders = height - 2.0 * kHeadRadius + 0.02;  // the head sits on the body
  a.parts.push_back(LocalBox({0.0, 0.0, 0.5 * shoulders}, {0.15, 0.225, 0.5 * shoulders}, reflectivity));
  a.parts.push_back(Sphere{{0.0, 0.0, height - kHeadRadius}, kHeadRadius, reflectivity});
  a.body = LocalBox({0.0, 0.0, 0.5 * height}, {0.15, 0.225, 0.5 * height}, reflectivity);
  return a;
}

Actor MakeVehicle(ActorMotion motion, float reflectivity, ActorRole role, const Eigen::Vector3d& size) {
  Actor a;
  a.kind = ActorKind::Vehicle;
  a.role = role;
  a.motion = std::move(motion);
  a.body = LocalBox({0.0, 0.0, 0.5 * size.z()}, 0.5 * size, reflectivity);
  a.parts.push_back(a.body);
  return a;
}

Actor MakeDoor(const Swing& swing, double width, double height, float reflectivity) {
  Actor a;
  a.kind = ActorKind::Door;
  a.role = ActorRole::Door;
  a.motion = swing;
  a.body = LocalBox({0.5 * width, 0.0, 0.5 * height}, {0.5 * width, 0.5 * kDoorThickness, 0.5 * height},
                    reflectivity);
  a.parts.push_back(a.body);
  return a;
}

ActorSet::ActorSet(std::vector<Actor> actors, std::optional<Heightfield> ground)
    : actors_(std::move(actors)), ground_(std::move(ground)) {}

std::size_t ActorSet::Count(ActorKind kind) const {
  return static_cast<std::size_t>(
      std::count_if(actors_.begin(), actors_.end(), [&](const Actor& a) { return a.kind == kind; }));
}

std::size_t ActorSet::Count(ActorRole role) const {
  return static_cast<std::size_t>(
      std::count_if(actors_.begin(), actors_.end(), [&](const Actor& a) { return a.role == role; }));
}

Eigen::Isometry3d ActorFrame(const Actor& actor, double t, const std::optional<Heightfield>& ground) {
  const GroundPose pose = PoseOf(actor.motion, t);
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear() = Eigen::AngleAxisd(pose.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double z = ground ? ground->Height(pose.position.x(), pose.position.y()) : 0.0;
  frame.translation() << pose.position, z;
  return frame;
}

Box BodyInWorld(const Actor& actor, const Eigen::Isometry3d& frame) {
  return std::get<Box>(ToWorld(actor.body, frame));
}

Eigen::Isometry3d ActorSet::FrameAt(std::size_t actor, double t) const {
  return ActorFrame(actors_[actor], t, ground_);
}

bool ActorSet::MovingAt(std::size_t actor, double t) const {
  const Actor& a = actors_[actor];
  const Eigen::Vector3d now = BodyInWorld(a, FrameAt(actor, t)).center;
  const Eigen::Vector3d before = BodyInWorld(a, FrameAt(actor, t - kMovingWindow)).center;
  return (now - before).norm() > kMovingDistance;
}

std::optional<ActorFootprint> ActorSet::FootprintAt(std::size_t actor, double t) const {
  if (!actors_[actor].PresentAt(t)) return std::nullopt;
  return ActorFootprint{actor, BodyInWorld(actors_[actor], FrameAt(actor, t)), MovingAt(actor, t)};
}

std::vector<ActorFootprint> ActorSet::FootprintsAt(double t) const {
  std::vector<ActorFootprint> out;
  for (std::size_t i = 0; i < actors_.size(); ++i) {
    if (auto footprint = FootprintAt(i, t)) out.push_back(*footprint);
  }
  return out;
}

std::vector<ActorSet::Reach> ActorSet::ReachDuring(double t_from, double t_to) const {
  std::vector<Reach> out;
  const int steps = std::max(1, static_cast<int>(std::ceil((t_to - t_from) / kReachStep)));
  std::vector<Eigen::Vector3d> origins(static_cast<std::size_t>(steps) + 1);
  for (std::size_t i = 0; i < actors_.size(); ++i) {
    const Actor& a = actors_[i];
    if (a.vanish < t_from || a.appear > t_to) continue;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(kForever), hi = -lo;
    double largest_step = 0.0;
    for (int k = 0; k <= steps; ++k) {
      const double t = t_from + (t_to - t_from) * k / steps;
      origins[static_cast<std::size_t>(k)] = FrameAt(i, t).translation();
      lo = lo.cwiseMin(origins[static_cast<std::size_t>(k)]);
      hi = hi.cwiseMax(origins[static_cast<std::size_t>(k)]);
      if (k > 0) {
        largest_step = std::max(largest_step, (origins[static_cast<std::size_t>(k)] -
                                               origins[static_cast<std::size_t>(k) - 1]).norm());
      }
    }
    const double reach = HorizontalReach(a.body);
    const double half_height = 0.5 * a.height();
    const Eigen::Vector3d center = 0.5 * (lo + hi) + Eigen::Vector3d(0.0, 0.0, half_height);
    const double radius = 0.5 * (hi - lo).norm() + std::hypot(reach, half_height) + largest_step + 0.05;
    out.push_back({i, center, radius});
  }
  return out;
}

void ActorSet::PoseForColumn(const std::vector<Reach>& reach, double t, const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& forward, const Eigen::Vector3d& plane_normal,
                             double max_range, std::vector<PosedPart>* out) const {
  out->clear();
  for (const Reach& r : reach) {
    const Eigen::Vector3d to = r.center - origin;
    // Every beam of the column lies in its half-plane, so a sphere off that plane or behind the
    // sensor cannot be hit by any of them.
    if (std::abs(plane_normal.dot(to)) > r.radius || forward.dot(to) < -r.radius ||
        to.norm() > max_range + r.radius) {
      continue;
    }
    if (!actors_[r.actor].PresentAt(t)) continue;
    const Eigen::Isometry3d frame = FrameAt(r.actor, t);
    const PointLabel label = MovingAt(r.actor, t) ? PointLabel::Moving : PointLabel::Resting;
    for (const ActorPart& part : actors_[r.actor].parts) out->push_back({ToWorld(part, frame), label});
  }
}

PointLabel ActorSet::Intersect(const std::vector<PosedPart>& parts, const Ray& ray, double t_min,
                               Hit& best) {
  PointLabel label = PointLabel::Static;
  for (const PosedPart& posed : parts) {
    const bool hit = std::visit([&](const auto& shape) { return shape.Intersect(ray, t_min, best); },
                                posed.part);
    if (hit) label = posed.label;
  }
  return label;
}

}  // namespace dammloam::sim
