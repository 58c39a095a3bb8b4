#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tools/simulate/scene.hpp"
#include "tools/simulate/trajectory.hpp"

namespace dammloam::sim {

enum class SceneKind {
  Corridor,
  Zigzag,
  Outdoor,
  Repetitive,
  CorridorReturn,
  LongCorridor,
  Tunnel,
  EndlessCorridor,
  StraightCorridor,
  Campus,
  CampusLong,
  TwoFloor,
  Warehouse
};

// What a scene is for, in one line each:
//  corridor        straight featureless corridor, no end walls: degenerate along x (paper case)
//  zigzag          corridor with door recesses and pillars, zig-zag drive
//  outdoor         buildings, trees and poles on uneven ground, closed ~40 x 30 m loop
//  repetitive      identical 10 m corridor segments with periodic doors (loop-closure aliasing)
//  corridor-return corridor driven to a U-turn and back along the other side
// Fixed-size scenes for the realistic carriers (presets.hpp); their walks end where planned:
//  long-corridor     130 x 2.4 x 2.8 m, five 5 cm door recesses, end walls; 88 m out, U-turn
//                    (r 0.5 m), back to near the start
//  tunnel            120 m circular tunnel (r 2.6 m, flat floor 1.1 m below the axis), three
//                    pipes along one side, ceiling lamps every 10-15 m, end walls; 110 m one way
//  endless-corridor  460 x 2.4 m corridor, a few recesses; 200 m out and back in the middle, the
//                    end walls stay more than 120 m away
//  straight-corridor 60 x 2.4 m, three 5 cm recesses; driven straight from x = 2 to x = 58
//  campus            ~300 m outdoor loop (105 x 52 m) between buildings, trees and poles on
//                    uneven ground; walked once round, back to the start
// Scenes where odometry drifts and loop closure is tempted (drift_scenes.hpp):
//  campus-long       ~1.55 km over a 3 x 2 grid of 85 x 65 m blocks (buildings, a park, an
//                    open field, trees, poles, parked cars, rolling ground); streets revisited,
//                    some in the opposite direction
//  two-floor         a ring corridor on two identical floors 3 m apart, joined by a staircase;
//                    round floor 1, up the stairs, round floor 2 right above
//  warehouse         five identical aisles between pallet racks, driven up and down, two again
std::vector<std::string> SceneNames();
std::optional<SceneKind> ParseSceneKind(std::string_view name);
std::string_view SceneName(SceneKind kind);
double DefaultSpeed(SceneKind kind);

// A door recess in a corridor's side wall: the opening spans x +- half_width at the wall
// y = wall_y, its back (where the static door stands) is at y = back_y.
struct DoorRecess {
  double x = 0.0;
  int side = 1;  // +1: the left wall (y > 0), -1: the right wall
  double wall_y = 0.0, back_y = 0.0;
  double half_width = 0.5;
  double height = 2.1;
};

// Where moving actors may go (actor_layouts.hpp). It only describes the scene: the primitives
// and so every static run stay exactly what they are.
struct SceneLayout {
  std::optional<Bounds2d> corridor;  // floor between the side walls; none: open ground
  std::vector<DoorRecess> doors;
};

struct World {
  Scene scene;  // already built
  MotionSpec motion;
  SceneLayout layout;
};

// `speed` in m/s (<= 0: the scene's default); `duration` in seconds sizes the corridor scenes so
// the whole drive stays inside them. The fixed-size scenes plan their walk to end (and stand
// still) 2 s before `duration` (MotionSpec::arrive_time; used by the non-constant carriers).
// Door recesses of the plain office corridors (long-, endless- and straight-corridor).
inline constexpr double kShallowRecess = 0.05;  // metres
inline constexpr double kMaxRecessDepth = 1.0;
World BuildWorld(SceneKind kind, double speed, double duration,
                 double recess_depth = kShallowRecess);

}  // namespace dammloam::sim
