#pragma once
#include <cstdint>

#include "tools/simulate/actors.hpp"
#include "tools/simulate/scenes.hpp"
#include "tools/simulate/trajectory.hpp"

// Which moving actors a run has, and placing them in its scene around the carrier's walk.
namespace dammloam::sim {

// Counts of 0 (the default) mean none: a run without actors.
struct ActorConfig {
  int walkers = 0;        // pedestrians on routes of their own, both ways, with stops and turns
  int close_passes = 0;   // of the walkers: pass the sensor within 1 m (centre to sensor)
  int standing = 0;       // pedestrians standing still the whole run (open scenes)
  int groups = 0;         // 3-5 people side by side keeping pace with the carrier for a while
  int traffic = 0;        // vehicles going round a lane of their own (open scenes only)
  bool park_and_leave = false;  // a car drives in and parks; a parked car drives off
  int doors = 0;          // doors of the corridor's recesses that swing open
  bool follow_me = false; // one person walking ahead of the carrier on its path, all the way

  double walk_speed_min = 0.8, walk_speed_max = 1.6;   // m/s
  double height_min = 1.5, height_max = 1.9;           // m, per pedestrian
  double stop_min = 2.0, stop_max = 8.0;               // s standing at a walker's stop
  double drive_speed_min = 3.0, drive_speed_max = 10.0;  // m/s
  double group_time_min = 10.0, group_time_max = 30.0;   // s keeping pace with the carrier
  double group_offset_min = 1.5, group_offset_max = 2.5;  // m beside the carrier (open scenes)
  double follow_distance = 2.0;                        // m ahead of the carrier
  double door_open_time = 1.5;                         // s from closed to open
  double sensor_clearance = 0.5;  // m: no actor's body ever comes closer to the sensor
  // Where an actor appears or vanishes (outside its walk or drive), the sensor is at least this
  // far away, metres: pedestrians, vehicles.
  double pop_distance = 8.0, vehicle_pop_distance = 20.0;

  bool any() const {
    return walkers > 0 || standing > 0 || groups > 0 || traffic > 0 || park_and_leave || doors > 0 ||
           follow_me;
  }
};

// Places the configured actors in `world` so that none comes within sensor_clearance of the
// carrier's sensor during the planned `duration` (seconds), none overlaps another or the static
// scene, and they stay on the corridor floor or the open ground. Randomness comes from `seed`
// through a stream of its own. What cannot be placed after many tries is left out.
ActorSet PlaceActors(const ActorConfig& config, const World& world, const Trajectory& trajectory,
                     double duration, std::uint64_t seed);

}  // namespace dammloam::sim
