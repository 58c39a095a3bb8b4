#pragma once
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <variant>
#include <vector>

#include "tools/simulate/trajectory.hpp"

// How a moving actor (actors.hpp) gets from place to place. Every motion is a pure function of
// the drive time t: seconds since the start of scan 0, the clock of Trajectory::Pose. Positions
// are on the ground plane; the actor set puts them on the floor or the heightfield.
namespace dammloam::sim {

inline constexpr double kForever = std::numeric_limits<double>::infinity();

// Where an actor's origin is and which way it faces (yaw, rad, counter-clockwise from +x).
struct GroundPose {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double yaw = 0.0;
};

struct Stop {
  double at = 0.0;        // metres along the route
  double duration = 0.0;  // seconds standing there
};

// Walking or driving along a polyline at one speed, standing still at its stops. Before
// start_time it waits at the first point; after the end it waits at the last one, or, when
// closed, goes round again. Heading is the direction of the current leg, so corners are turns.
class Route {
 public:
  Route() : Route(Eigen::Vector2d::Zero(), 0.0) {}
  Route(std::vector<Eigen::Vector2d> points, double speed, double start_time,
        std::vector<Stop> stops = {}, bool closed = false);
  // Standing at `position`, facing `yaw`, the whole time.
  Route(const Eigen::Vector2d& position, double yaw);

  GroundPose At(double t) const { return AtDistance(DistanceAt(t)); }
  GroundPose AtDistance(double s) const;
  double DistanceAt(double t) const;
  // The first time it is `s` metres along (s clamped to the route).
  double TimeAt(double s) const;
  // When it reaches the end of an open route (kForever when closed).
  double end_time() const;
  double length() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }
  double speed() const { return speed_; }
  double start_time() const { return start_time_; }
  bool closed() const { return closed_; }
  const std::vector<Eigen::Vector2d>& points() const { return points_; }
  const std::vector<Stop>& stops() const { return stops_; }

 private:
  std::vector<Eigen::Vector2d> points_;  // closed: the first point repeated at the end
  std::vector<double> cumulative_;       // arc length at each point
  double speed_ = 0.0, start_time_ = 0.0;
  std::vector<Stop> stops_;              // sorted by `at`, inside (0, length)
  bool closed_ = false;
  double standing_yaw_ = 0.0;            // heading of a route without legs
};

// A door leaf turning about its vertical hinge from closed to open, with a smooth start and end.
struct Swing {
  Eigen::Vector2d hinge = Eigen::Vector2d::Zero();
  double closed_yaw = 0.0;   // from the hinge towards the free edge, door closed
  double open_angle = 0.0;   // rad, signed (counter-clockwise > 0)
  double open_time = kForever;
  double duration = 1.5;     // seconds from closed to fully open

  GroundPose At(double t) const;
};

// Walks on the carrier's own path, `distance` metres in a straight line ahead of the carrier's
// path point: it keeps that gap through turns, waits when the carrier stands and faces the way
// the path goes.
struct Leader {
  std::shared_ptr<const Trajectory> carrier;
  double distance = 2.0;

  GroundPose At(double t) const;
};

// Keeps pace with the carrier from join_time to leave_time, `along` metres ahead of and
// `lateral` metres left of the carrier's path point. Before, it walks the same line at
// speed_before (0: it waits there for the carrier); after, at speed_after (it walks on).
struct Companion {
  std::shared_ptr<const Trajectory> carrier;
  double along = 0.0, lateral = 1.5;
  double join_time = 0.0, leave_time = 0.0;
  double speed_before = 0.8, speed_after = 1.6;

  GroundPose At(double t) const;
};

using ActorMotion = std::variant<Route, Swing, Leader, Companion>;

GroundPose PoseOf(const ActorMotion& motion, double t);

}  // namespace dammloam::sim
