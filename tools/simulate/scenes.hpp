#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tools/simulate/scene.hpp"
#include "tools/simulate/trajectory.hpp"

namespace dammloam::sim {

enum class SceneKind { Corridor, Zigzag, Outdoor, Repetitive, CorridorReturn };

// What a scene is for, in one line each:
//  corridor        straight featureless corridor, no end walls: degenerate along x (paper case)
//  zigzag          corridor with door recesses and pillars, zig-zag drive
//  outdoor         buildings, trees and poles on uneven ground, closed ~40 x 30 m loop
//  repetitive      identical 10 m corridor segments with periodic doors (loop-closure aliasing)
//  corridor-return corridor driven to a U-turn and back along the other side
std::vector<std::string> SceneNames();
std::optional<SceneKind> ParseSceneKind(std::string_view name);
std::string_view SceneName(SceneKind kind);
double DefaultSpeed(SceneKind kind);

struct World {
  Scene scene;  // already built
  MotionSpec motion;
};

// `speed` in m/s (<= 0: the scene's default); `duration` in seconds sizes the corridor scenes so
// the whole drive stays inside them.
World BuildWorld(SceneKind kind, double speed, double duration);

}  // namespace dammloam::sim
