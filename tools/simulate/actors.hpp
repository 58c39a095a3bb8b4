#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include "tools/simulate/actor_motion.hpp"
#include "tools/simulate/primitives.hpp"

// Moving things of a scene: pedestrians, vehicles and doors, each a few primitives posed by its
// motion (actor_motion.hpp) at the drive time t (seconds since the start of scan 0). The
// simulator casts every beam against them at the beam's own firing time and labels the points
// it gets from them.
namespace dammloam::sim {

enum class ActorKind { Pedestrian, Vehicle, Door };
// Why an actor is in the scene, for tests and benchmarks that look for one in particular.
enum class ActorRole { Walker, Companion, Leader, Traffic, Parking, Leaving, Door };

// A part of an actor's body in its own frame: x forward, y left, z up, origin on the ground.
using ActorPart = std::variant<Box, Sphere>;

struct Actor {
  ActorKind kind = ActorKind::Pedestrian;
  ActorRole role = ActorRole::Walker;
  ActorMotion motion;
  std::vector<ActorPart> parts;
  Box body;  // in the actor frame, holds every part: the footprint and what "moved" refers to
  double appear = -kForever, vanish = kForever;  // in the scene only within [appear, vanish]

  bool PresentAt(double t) const { return t >= appear && t <= vanish; }
  double height() const { return body.center.z() + body.half_size.z(); }
};

// Body about 0.45 m wide and 0.3 m deep up to the shoulders, a head on top; `height` is the
// top of the head above the feet.
Actor MakePedestrian(ActorMotion motion, double height, float reflectivity,
                     ActorRole role = ActorRole::Walker);
// A box `size` (length, width, height) long along the heading.
Actor MakeVehicle(ActorMotion motion, float reflectivity, ActorRole role = ActorRole::Traffic,
                  const Eigen::Vector3d& size = Eigen::Vector3d(4.5, 1.8, 1.5));
// A leaf `width` x `height`, 4 cm thick, from the hinge along the swing's yaw.
Actor MakeDoor(const Swing& swing, double width, double height, float reflectivity);

// world_from_actor at t (present or not): origin on the ground (the heightfield, else z = 0),
// turned about z only.
Eigen::Isometry3d ActorFrame(const Actor& actor, double t, const std::optional<Heightfield>& ground);
Box BodyInWorld(const Actor& actor, const Eigen::Isometry3d& frame);

// What a point on an actor is labelled (labels/NNNNNN.bin, docs/presets.md).
enum class PointLabel : std::uint8_t { Static = 0, Moving = 1, Resting = 2 };
// An actor is moving at t when its body centre moved more than kMovingDistance since
// t - kMovingWindow.
inline constexpr double kMovingDistance = 0.3, kMovingWindow = 1.0;

// One actor's body at a time: an oriented box in the world.
struct ActorFootprint {
  std::size_t actor = 0;  // index in ActorSet::actors()
  Box box;
  bool moving = false;
};

// Per-beam work for the ray caster: an actor's parts in the world at a column's firing time.
struct PosedPart {
  ActorPart part;
  PointLabel label = PointLabel::Static;
};

// The actors of a run. Heights come from the ground (heightfield) or the floor z = 0.
class ActorSet {
 public:
  ActorSet() = default;
  ActorSet(std::vector<Actor> actors, std::optional<Heightfield> ground);

  bool empty() const { return actors_.empty(); }
  std::size_t size() const { return actors_.size(); }
  const std::vector<Actor>& actors() const { return actors_; }
  std::size_t Count(ActorKind kind) const;
  std::size_t Count(ActorRole role) const;

  // world_from_actor at t (whether present or not): origin on the ground, yaw only.
  Eigen::Isometry3d FrameAt(std::size_t actor, double t) const;
  bool MovingAt(std::size_t actor, double t) const;
  // Body of a present actor (nullopt when it is not in the scene at t).
  std::optional<ActorFootprint> FootprintAt(std::size_t actor, double t) const;
  std::vector<ActorFootprint> FootprintsAt(double t) const;

  // Ray casting in two steps keeps the per-beam cost small for a crowd. Per scan: a sphere
  // around each actor present during [t_from, t_to] that holds its body for the whole time.
  struct Reach {
    std::size_t actor = 0;
    Eigen::Vector3d center;
    double radius = 0.0;
  };
  std::vector<Reach> ReachDuring(double t_from, double t_to) const;
  // Per column: the parts, posed at the column's time t, of the actors whose reach crosses the
  // column's half-plane (through `origin`, spanned by `forward` and the plane's up direction,
  // normal `plane_normal`) within max_range. `out` is cleared first.
  void PoseForColumn(const std::vector<Reach>& reach, double t, const Eigen::Vector3d& origin,
                     const Eigen::Vector3d& forward, const Eigen::Vector3d& plane_normal,
                     double max_range, std::vector<PosedPart>* out) const;
  // Nearest part hit closer than best.t: updates `best`, returns its label (Static: none).
  static PointLabel Intersect(const std::vector<PosedPart>& parts, const Ray& ray, double t_min,
                              Hit& best);

 private:
  std::vector<Actor> actors_;
  std::optional<Heightfield> ground_;
};

}  // namespace dammloam::sim
