#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "tools/simulate/actors.hpp"
#include "tools/simulate/scenes.hpp"
#include "tools/simulate/trajectory.hpp"

// The checks an actor must pass to be placed (actor_layouts.cpp): it keeps clear of the static
// scene, of the carrier's sensor and of the actors placed before it. Everything is sampled on
// a clock of kPlacementStep seconds over the planned run.
namespace dammloam::sim {

inline constexpr double kPlacementStep = 0.1;

// An actor's body at every sample time of the run (nullopt while it is not in the scene).
struct ActorTrack {
  std::vector<std::optional<Box>> bodies;
};

class PlacementSpace {
 public:
  PlacementSpace(const World& world, const Trajectory& trajectory, double duration);

  double duration() const { return duration_; }
  const std::optional<Heightfield>& ground() const { return ground_; }
  const std::optional<Bounds2d>& corridor() const { return corridor_; }
  Eigen::Vector3d SensorAt(double t) const;  // exact, from the trajectory
  const std::vector<Eigen::Vector3d>& sensor_samples() const { return sensor_; }

  ActorTrack Track(const Actor& actor) const;
  // The body never overlaps a wall, building, tree or pillar (with `margin` metres to spare)
  // and stays on the corridor floor, if the scene is a corridor.
  bool ClearOfScene(const ActorTrack& track, double margin) const;
  // A body placed at one pose, same rules.
  bool ClearOfScene(const Box& body, double margin) const;
  // Nearest the body ever gets to the sensor (box to sensor point), refined between samples.
  double SensorGap(const Actor& actor, const ActorTrack& track) const;
  // Nearest the body centre gets to the sensor, horizontally, at the samples.
  double ClosestPass(const ActorTrack& track) const;
  bool ClearOfActors(const ActorTrack& track) const;
  // Horizontal distance from the sensor where the actor appears and vanishes within the run
  // (infinite when it is there from start to end).
  double PopDistance(const Actor& actor) const;

  void Accept(Actor actor, ActorTrack track);
  // Forgets the actors accepted after the first `count` (a group that did not fit as a whole).
  void Truncate(std::size_t count);
  const std::vector<Actor>& accepted() const { return actors_; }
  std::vector<Actor> TakeActors() { return std::move(actors_); }

 private:
  // A static obstacle's outline in the ground plane, an oriented rectangle or a circle, and the
  // heights it spans. A sphere's circle depends on the height of what it may touch.
  struct Outline {
    Eigen::Vector2d center;
    Eigen::Matrix2d axes = Eigen::Matrix2d::Identity();  // columns: the rectangle's axes
    Eigen::Vector2d half = Eigen::Vector2d::Zero();
    double radius = 0.0;  // > 0: a circle
    double z_min = -kForever, z_max = kForever;
    std::optional<Sphere> sphere;
  };
  void AddOutlines(const Scene& scene);
  // The obstacle's outline at the heights [z_min, z_max], if it reaches them.
  static std::optional<Outline> Slice(const Outline& o, double z_min, double z_max);
  static bool Overlaps(const Outline& a, const Outline& b);
  static Outline OutlineOf(const Box& body, double margin);
  std::vector<std::size_t> OutlinesNear(const Eigen::Vector2d& min, const Eigen::Vector2d& max) const;

  double duration_ = 0.0;
  const Trajectory* trajectory_ = nullptr;
  std::optional<Heightfield> ground_;
  std::optional<Bounds2d> corridor_;
  std::vector<Eigen::Vector3d> sensor_;  // at every sample time
  std::vector<Outline> outlines_;
  // Outlines by grid cell, so a body is tested only against the obstacles near it.
  Eigen::Vector2d grid_min_ = Eigen::Vector2d::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::size_t>> cells_;
  std::vector<Actor> actors_;
  std::vector<ActorTrack> tracks_;
};

}  // namespace dammloam::sim
