#pragma once
#include <Eigen/Core>
#include <vector>

#include "tools/simulate/actors.hpp"

// The space actors occupied during a time window, for counting "ghost" points: points a map
// kept where an actor was and has since left. Times are the actors' drive time (seconds since
// scan 0 starts; Simulator::ActorSweptVolume takes its own clock).
namespace dammloam::sim {

class SweptVolume {
 public:
  // Bodies sampled every `step` seconds in [t_from, t_to], each grown by `margin` metres so that
  // points measured on a surface (with range noise) count as inside. `clearance` raises each
  // body's bottom off its feet: the ground an actor walked on is still there after it left, so
  // a count of what a map kept of the actor leaves that ground out.
  SweptVolume(const ActorSet& actors, double t_from, double t_to, double step = 0.05,
              double margin = 0.05, double clearance = 0.0);

  // Inside some actor's body at some sample time of the window.
  bool Occupied(const Eigen::Vector3d& p) const;
  // Occupied, but inside no actor's body at t_to: the actor has left that place since.
  bool Vacated(const Eigen::Vector3d& p) const;
  // Inside some actor's body at t_to (a car parked there, a person standing).
  bool OccupiedAtEnd(const Eigen::Vector3d& p) const;

 private:
  static bool Inside(const Box& box, const Eigen::Vector3d& p);
  const std::vector<std::size_t>& Near(const Eigen::Vector3d& p) const;

  std::vector<Box> swept_;  // grown bodies, one per actor and sample where it moved
  std::vector<Box> now_;    // grown bodies at t_to
  // Swept bodies by 2-D grid cell: a query tests only the few bodies of its cell.
  Eigen::Vector2d grid_min_ = Eigen::Vector2d::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::size_t>> cells_;
};

}  // namespace dammloam::sim
