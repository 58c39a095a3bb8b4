#include "tools/simulate/scenes.hpp"
#include "tools/simulate/angles.hpp"
#include "tools/simulate/drift_scenes.hpp"
#include "tools/simulate/scene_parts.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace dammloam::sim {

namespace {


struct CorridorShape {
  double x0 = -10.0, x1 = 50.0;
  double width = 2.4, height = 2.8;
};

// Door recesses cut into a side wall. side = +1 for the left wall (y > 0), -1 for the right.
struct Door {
  double x = 0.0;
  int side = 1;
};
constexpr double kDoorWidth = 1.0, kDoorHeight = 2.1, kDoorDepth = 0.4;

Bounds2d CorridorFloor(const CorridorShape& c) {
  return {Eigen::Vector2d(c.x0, -0.5 * c.width), Eigen::Vector2d(c.x1, 0.5 * c.width)};
}

void AddFloorAndCeiling(Scene& scene, const CorridorShape& c, double extra_width) {
  const double half = 0.5 * c.width + extra_width;
  scene.Add(HorizontalRect(c.x0, c.x1, -half, half, 0.0, kFloor));
  scene.Add(HorizontalRect(c.x0, c.x1, -half, half, c.height, kCeiling));
}

// One side wall with its door recesses (gap, lintel, jambs, recess back and top).
void AddSideWall(Scene& scene, SceneLayout& layout, const CorridorShape& c, int side,
                 std::vector<double> doors, double depth = kDoorDepth) {
  const double y = side * 0.5 * c.width, y_back = side * (0.5 * c.width + depth);
  std::sort(doors.begin(), doors.end());
  double x = c.x0;
  for (const double d : doors) {
    const double a = d - 0.5 * kDoorWidth, b = d + 0.5 * kDoorWidth;
    scene.Add(WallAlongX(x, a, y, 0.0, c.height, kWall));
    scene.Add(WallAlongX(a, b, y, kDoorHeight, c.height, kWall));  // lintel
    scene.Add(WallAlongX(a, b, y_back, 0.0, kDoorHeight, kDoor));  // the door itself
    scene.Add(WallAlongY(std::min(y, y_back), std::max(y, y_back), a, 0.0, kDoorHeight, kWall));
    scene.Add(WallAlongY(std::min(y, y_back), std::max(y, y_back), b, 0.0, kDoorHeight, kWall));
    scene.Add(HorizontalRect(a, b, std::min(y, y_back), std::max(y, y_back), kDoorHeight, kWall));
    layout.doors.push_back({d, side, y, y_back, 0.5 * kDoorWidth, kDoorHeight});
    x = b;
  }
  scene.Add(WallAlongX(x, c.x1, y, 0.0, c.height, kWall));
}

void AddPillar(Scene& scene, const CorridorShape& c, double x, int side) {
  const double wall = side * 0.5 * c.width, face = wall - side * 0.3;
  scene.Add(AxisBox({x - 0.2, std::min(wall, face), 0.0}, {x + 0.2, std::max(wall, face), c.height},
                    kPillar));
}

Path StraightPath(double length) { return Path().Line(length); }

World Corridor(double speed, double duration, bool go_and_return) {
  World w;
  const double travel = speed * duration;
  CorridorShape c;
  constexpr double kTurnRadius = 0.6;
  const double out = go_and_return ? std::max(5.0, 0.5 * (travel - kPi * kTurnRadius)) : travel;
  c.x1 = std::max(60.0 + c.x0, out + 10.0);
  AddFloorAndCeiling(w.scene, c, 0.0);
  AddSideWall(w.scene, w.layout, c, +1, {});
  AddSideWall(w.scene, w.layout, c, -1, {});
  w.layout.corridor = CorridorFloor(c);
  // A real corridor ends somewhere: two end walls, far away for most of the drive, are the only
  // (weak) constraint along its axis. That is the degenerate case of the paper.
  w.scene.Add(WallAlongY(-0.5 * c.width, 0.5 * c.width, c.x0, 0.0, c.height, kWall));
  w.scene.Add(WallAlongY(-0.5 * c.width, 0.5 * c.width, c.x1, 0.0, c.height, kWall));
  if (go_and_return) {
    w.motion.path = Path({Eigen::Vector2d(0.0, -kTurnRadius), 0.0})
                        .Line(out)
                        .Arc(kTurnRadius, kPi)
                        .Line(out + 5.0);
  } else {
    w.motion.path = StraightPath(c.x1 - 1.0);
  }
  w.motion.speed = speed;
  w.motion.sensor_height = 1.2;
  if (go_and_return) w.motion.wobble.lateral = 0.02;
  return w;
}

World Zigzag(double speed, double duration) {
  World w;
  CorridorShape c;
  c.width = 4.0;
  c.height = 3.0;
  c.x1 = std::max(60.0 + c.x0, speed * duration + 10.0);
  AddFloorAndCeiling(w.scene, c, kDoorDepth);
  // Irregular spacing (fixed layout seed) so no two stretches look alike.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> gap(4.0, 9.0);
  std::vector<double> doors[2];
  for (double x = c.x0 + 3.0; x < c.x1 - 2.0; x += gap(rng)) doors[rng() % 2].push_back(x);
  AddSideWall(w.scene, w.layout, c, +1, doors[0]);
  AddSideWall(w.scene, w.layout, c, -1, doors[1]);
  w.layout.corridor = CorridorFloor(c);
  for (double x = c.x0 + 5.0; x < c.x1 - 2.0; x += gap(rng)) {
    const int side = rng() % 2 ? 1 : -1;
    const auto& mine = doors[side > 0 ? 0 : 1];
    const bool clear = std::none_of(mine.begin(), mine.end(),
                                    [&](double d) { return std::abs(d - x) < 1.2; });
    if (clear) AddPillar(w.scene, c, x, side);
  }
  w.motion.path = StraightPath(c.x1 - 1.0);
  w.motion.speed = speed;
  w.motion.sensor_height = 1.2;
  w.motion.zigzag_amplitude = 0.8;
  w.motion.zigzag_wavelength = 10.0;
  return w;
}

World Repetitive(double speed, double duration) {
  World w;
  CorridorShape c;
  constexpr double kSegment = 10.0;
  c.x1 = c.x0 + kSegment * std::ceil(std::max(60.0, speed * duration + 20.0) / kSegment);
  AddFloorAndCeiling(w.scene, c, kDoorDepth);
  std::vector<double> doors;
  for (double x = c.x0 + 3.0; x < c.x1; x += kSegment) {
    doors.push_back(x);
    AddPillar(w.scene, c, x + 4.0, -1);
  }
  AddSideWall(w.scene, w.layout, c, +1, doors);
  AddSideWall(w.scene, w.layout, c, -1, {});
  w.layout.corridor = CorridorFloor(c);
  w.motion.path = StraightPath(c.x1 - 1.0);
  w.motion.speed = speed;
  w.motion.sensor_height = 1.2;
  return w;
}

// A rounded rectangle loop: straight sides of (length - 2r) x (width - 2r), corners of radius r.
Path RoundedRectangle(double length, double width, double r) {
  Path p;
  for (int i = 0; i < 2; ++i) p.Line(length - 2 * r).Arc(r, kPi / 2).Line(width - 2 * r).Arc(r, kPi / 2);
  return p;
}

// Trees and poles 3-4.5 m beside the road every 5-11 m, on either side (layout from `seed`).
void AddRoadside(Scene& scene, const Path& road, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (double s = 2.0; s < road.length(); s += 5.0 + 6.0 * uniform(rng)) {
    const Path::State st = road.At(s);
    const Eigen::Vector2d left(-std::sin(st.heading), std::cos(st.heading));
    const double side = uniform(rng) < 0.5 ? 1.0 : -1.0;
    const Eigen::Vector2d xy = st.position + side * (3.0 + 1.5 * uniform(rng)) * left;
    if (uniform(rng) < 0.2) {
      scene.Add(Cylinder{xy, 0.08, -1.0, 5.0, kPole});
      continue;
    }
    const double trunk_r = 0.15 + 0.15 * uniform(rng), trunk_h = 2.2 + 1.3 * uniform(rng);
    const double crown_r = 1.2 + 1.0 * uniform(rng);
    scene.Add(Cylinder{xy, trunk_r, -1.0, trunk_h, kTrunk});
    scene.Add(Sphere{Eigen::Vector3d(xy.x(), xy.y(), trunk_h + 0.8 * crown_r), crown_r, kCrown});
  }
}

World Outdoor(double speed) {
  World w;
  constexpr double kLength = 40.0, kWidth = 30.0, kCorner = 6.0;
  // Loop occupies x in [-6, 34], y in [0, 30]; the road is the path itself.
  w.scene.SetGround(Heightfield(
      0.0,
      {{0.12, Eigen::Vector2d(2 * kPi / 25.0, 2 * kPi / 60.0), 0.3},
       {0.05, Eigen::Vector2d(-2 * kPi / 40.0, 2 * kPi / 11.0), 1.7},
       {0.02, Eigen::Vector2d(2 * kPi / 6.3, 2 * kPi / 9.0), 0.9}},
      0.25f));

  auto building = [&](double x0, double y0, double x1, double y1, double h, double yaw_deg = 0.0) {
    Box b = AxisBox({x0, y0, -1.0}, {x1, y1, h}, kFacade);
    b.rotation = Eigen::AngleAxisd(yaw_deg * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    w.scene.Add(b);
  };
  // Inner block (inside the loop, >= 5 m from the road).
  building(0.0, 6.0, 12.0, 14.0, 9.0);
  building(16.0, 6.5, 27.0, 12.0, 6.0, 8.0);
  building(1.0, 18.0, 9.0, 24.0, 14.0);
  building(14.0, 17.0, 28.0, 24.0, 7.5, -5.0);
  // Outer ring of buildings (>= 6 m outside the road), with gaps between them.
  building(-10.0, -16.0, 6.0, -7.0, 12.0);
  building(10.0, -15.0, 22.0, -8.0, 8.0);
  building(26.0, -18.0, 40.0, -9.0, 16.0, 12.0);
  building(41.0, -4.0, 49.0, 12.0, 10.0);
  building(42.0, 16.0, 52.0, 34.0, 6.5, -7.0);
  building(-4.0, 37.0, 14.0, 45.0, 11.0);
  building(19.0, 38.0, 33.0, 46.0, 18.0);
  building(-22.0, 2.0, -14.0, 26.0, 9.0);
  // Trees and poles beside the road, irregularly spaced (fixed layout seed).
  const Path road = RoundedRectangle(kLength, kWidth, kCorner);
  AddRoadside(w.scene, road, 11);
  w.motion.path = road;
  w.motion.closed = true;
  w.motion.speed = speed;
  w.motion.sensor_height = 1.8;
  w.motion.ground = w.scene.ground();
  w.motion.wobble.lateral = 0.1;
  return w;
}

// --- Fixed-size scenes for the realistic carriers -------------------------------------------

constexpr double kArriveMargin = 2.0;    // s standing at the end of a planned walk

double ArriveTime(double duration) { return std::max(duration - kArriveMargin, 0.0); }

// A 2.4 x 2.8 m corridor from x0 to x1 with shallow door recesses and both end walls.
void AddPlainCorridor(World& w, double x0, double x1, const std::vector<double>& left,
                      const std::vector<double>& right, double recess_depth) {
  CorridorShape c;
  c.x0 = x0;
  c.x1 = x1;
  AddFloorAndCeiling(w.scene, c, recess_depth);
  AddSideWall(w.scene, w.layout, c, +1, left, recess_depth);
  AddSideWall(w.scene, w.layout, c, -1, right, recess_depth);
  w.scene.Add(WallAlongY(-0.5 * c.width, 0.5 * c.width, c.x0, 0.0, c.height, kWall));
  w.scene.Add(WallAlongY(-0.5 * c.width, 0.5 * c.width, c.x1, 0.0, c.height, kWall));
  w.layout.corridor = CorridorFloor(c);
}

// Out along the right half of the corridor, a U-turn to the left, back along the left half.
Path ThereAndBack(double x_start, double out, double back, double turn_radius) {
  return Path({Eigen::Vector2d(x_start, -turn_radius), 0.0}).Line(out).Arc(turn_radius, kPi).Line(back);
}

World LongCorridor(double speed, double duration, double recess_depth) {
  World w;
  AddPlainCorridor(w, 0.0, 130.0, {17.3, 58.6, 101.2}, {36.9, 83.4}, recess_depth);
  w.motion.path = ThereAndBack(5.0, 88.0, 87.0, 0.5);
  w.motion.speed = speed;
  w.motion.arrive_time = ArriveTime(duration);
  return w;
}

World EndlessCorridor(double speed, double duration, double recess_depth) {
  World w;
  AddPlainCorridor(w, 0.0, 460.0, {171.0, 262.8}, {224.5, 298.1}, recess_depth);
  w.motion.path = ThereAndBack(130.0, 200.0, 200.0, 0.5);
  w.motion.speed = speed;
  w.motion.arrive_time = ArriveTime(duration);
  return w;
}

World StraightCorridor(double speed, double duration, double recess_depth) {
  World w;
  AddPlainCorridor(w, 0.0, 60.0, {13.7, 44.6}, {29.2}, recess_depth);
  w.motion.path = Path({Eigen::Vector2d(2.0, -0.2), 0.0}).Line(56.0);
  w.motion.speed = speed;
  w.motion.arrive_time = ArriveTime(duration);
  return w;
}

World Tunnel(double speed, double duration) {
  World w;
  constexpr double kLength = 120.0, kRadius = 2.6, kAxisZ = 1.1;
  constexpr float kConcrete = 0.35f, kPipe = 0.6f, kLamp = 0.9f;
  const double half_floor = std::sqrt(kRadius * kRadius - kAxisZ * kAxisZ);
  w.scene.Add(CylinderX{{0.0, kAxisZ}, kRadius, 0.0, kLength, true, 0.0, kConcrete});
  w.scene.Add(HorizontalRect(0.0, kLength, -half_floor, half_floor, 0.0, kFloor));
  // Pipes along the right-hand wall (y < 0).
  w.scene.Add(CylinderX{{-1.9, 1.9}, 0.12, 0.0, kLength, false, -1e9, kPipe});
  w.scene.Add(CylinderX{{-2.05, 1.5}, 0.08, 0.0, kLength, false, -1e9, kPipe});
  w.scene.Add(CylinderX{{-2.1, 1.1}, 0.15, 0.0, kLength, false, -1e9, kPipe});
  // Lamps on the ceiling at slightly irregular spacing (fixed layout seed).
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> gap(10.0, 15.0);
  const double top = kAxisZ + kRadius;
  for (double x = 4.0 + gap(rng) * 0.5; x < kLength - 2.0; x += gap(rng)) {
    w.scene.Add(AxisBox({x - 0.6, -0.15, top - 0.3}, {x + 0.6, 0.15, top}, kLamp));
  }
  w.scene.Add(WallAlongY(-kRadius, kRadius, 0.0, 0.0, top, kConcrete));
  w.scene.Add(WallAlongY(-kRadius, kRadius, kLength, 0.0, top, kConcrete));
  w.layout.corridor = Bounds2d{Eigen::Vector2d(0.0, -half_floor), Eigen::Vector2d(kLength, half_floor)};
  w.motion.path = Path({Eigen::Vector2d(5.0, 0.4), 0.0}).Line(110.0);
  w.motion.speed = speed;
  w.motion.arrive_time = ArriveTime(duration);
  return w;
}

// The outdoor scene, generalised: a 105 x 52 m rounded loop (~300 m) with procedurally placed
// buildings inside and outside it, trees and poles along it, on gently uneven ground.
World Campus(double speed, double duration) {
  World w;
  constexpr double kLength = 105.0, kWidth = 52.0, kCorner = 8.0;
  // The loop occupies x in [-8, 97], y in [0, 52].
  w.scene.SetGround(Heightfield(
      0.0,
      {{0.15, Eigen::Vector2d(2 * kPi / 40.0, 2 * kPi / 70.0), 0.3},
       {0.06, Eigen::Vector2d(-2 * kPi / 45.0, 2 * kPi / 13.0), 1.7},
       {0.02, Eigen::Vector2d(2 * kPi / 6.3, 2 * kPi / 9.0), 0.9}},
      0.25f));
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto range = [&](double a, double b) { return a + (b - a) * uniform(rng); };
  auto building = [&](double x0, double y0, double x1, double y1) {
    Box b = AxisBox({x0, y0, -1.0}, {x1, y1, range(5.0, 18.0)}, kFacade);
    b.rotation = Eigen::AngleAxisd(range(-5.0, 5.0) * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    w.scene.Add(b);
  };
  // A row of buildings along x (from x0 to x1) between y = y_near and y_near +- depth.
  auto row_x = [&](double x0, double x1, double y_near, int away) {
    for (double x = x0 + range(0.0, 4.0); x < x1;) {
      const double width = std::min(range(8.0, 18.0), x1 - x), depth = range(6.0, 12.0);
      if (width > 4.0 && uniform(rng) < 0.8) {
        building(x, away > 0 ? y_near : y_near - depth, x + width, away > 0 ? y_near + depth : y_near);
      }
      x += width + range(3.0, 9.0);
    }
  };
  auto row_y = [&](double y0, double y1, double x_near, int away) {
    for (double y = y0 + range(0.0, 4.0); y < y1;) {
      const double width = std::min(range(8.0, 18.0), y1 - y), depth = range(6.0, 12.0);
      if (width > 4.0 && uniform(rng) < 0.8) {
        building(away > 0 ? x_near : x_near - depth, y, away > 0 ? x_near + depth : x_near, y + width);
      }
      y += width + range(3.0, 9.0);
    }
  };
  row_x(1.0, 88.0, 9.0, +1);     // inside the loop, along its south side
  row_x(1.0, 88.0, 43.0, -1);    // inside, along the north side
  row_x(-25.0, 115.0, -8.0, -1);  // outside, south
  row_x(-25.0, 115.0, 60.0, +1);  // outside, north
  row_y(2.0, 50.0, -16.0, -1);   // outside, west
  row_y(2.0, 50.0, 105.0, +1);   // outside, east
  const Path road = RoundedRectangle(kLength, kWidth, kCorner);
  AddRoadside(w.scene, road, 29);
  w.motion.path = road;
  w.motion.closed = false;  // once round, then stand at the start
  w.motion.speed = speed;
  w.motion.sensor_height = 1.8;
  w.motion.ground = w.scene.ground();
  w.motion.wobble.lateral = 0.1;
  w.motion.arrive_time = ArriveTime(duration);
  return w;
}

}  // namespace

std::vector<std::string> SceneNames() {
  return {"corridor",      "zigzag",           "outdoor",           "repetitive",
          "corridor-return", "long-corridor",  "tunnel", "endless-corridor", "straight-corridor",
          "campus", "campus-long", "two-floor", "warehouse"};
}

std::optional<SceneKind> ParseSceneKind(std::string_view name) {
  if (name == "corridor") return SceneKind::Corridor;
  if (name == "zigzag") return SceneKind::Zigzag;
  if (name == "outdoor") return SceneKind::Outdoor;
  if (name == "repetitive") return SceneKind::Repetitive;
  if (name == "corridor-return") return SceneKind::CorridorReturn;
  if (name == "long-corridor") return SceneKind::LongCorridor;
  if (name == "tunnel") return SceneKind::Tunnel;
  if (name == "endless-corridor") return SceneKind::EndlessCorridor;
  if (name == "straight-corridor") return SceneKind::StraightCorridor;
  if (name == "campus") return SceneKind::Campus;
  if (name == "campus-long") return SceneKind::CampusLong;
  if (name == "two-floor") return SceneKind::TwoFloor;
  if (name == "warehouse") return SceneKind::Warehouse;
  return std::nullopt;
}

std::string_view SceneName(SceneKind kind) {
  switch (kind) {
    case SceneKind::Corridor: return "corridor";
    case SceneKind::Zigzag: return "zigzag";
    case SceneKind::Outdoor: return "outdoor";
    case SceneKind::Repetitive: return "repetitive";
    case SceneKind::CorridorReturn: return "corridor-return";
    case SceneKind::LongCorridor: return "long-corridor";
    case SceneKind::Tunnel: return "tunnel";
    case SceneKind::EndlessCorridor: return "endless-corridor";
    case SceneKind::StraightCorridor: return "straight-corridor";
    case SceneKind::Campus: return "campus";
    case SceneKind::CampusLong: return "campus-long";
    case SceneKind::TwoFloor: return "two-floor";
    case SceneKind::Warehouse: return "warehouse";
  }
  return "unknown";
}

double DefaultSpeed(SceneKind kind) {
  return kind == SceneKind::Outdoor || kind == SceneKind::Campus || kind == SceneKind::CampusLong ? 1.5 : 1.0;
}

World BuildWorld(SceneKind kind, double speed, double duration, double recess_depth) {
  if (!(speed > 0.0)) speed = DefaultSpeed(kind);
  duration = std::max(duration, 0.0);
  World w;
  switch (kind) {
    case SceneKind::Corridor: w = Corridor(speed, duration, false); break;
    case SceneKind::Zigzag: w = Zigzag(speed, duration); break;
    case SceneKind::Outdoor: w = Outdoor(speed); break;
    case SceneKind::Repetitive: w = Repetitive(speed, duration); break;
    case SceneKind::CorridorReturn: w = Corridor(speed, duration, true); break;
    case SceneKind::LongCorridor: w = LongCorridor(speed, duration, recess_depth); break;
    case SceneKind::Tunnel: w = Tunnel(speed, duration); break;
    case SceneKind::EndlessCorridor: w = EndlessCorridor(speed, duration, recess_depth); break;
    case SceneKind::StraightCorridor: w = StraightCorridor(speed, duration, recess_depth); break;
    case SceneKind::Campus: w = Campus(speed, duration); break;
    case SceneKind::CampusLong: w = CampusLong(speed, ArriveTime(duration)); break;
    case SceneKind::TwoFloor: w = TwoFloor(ArriveTime(duration)); break;
    case SceneKind::Warehouse: w = Warehouse(ArriveTime(duration)); break;
  }
  w.scene.Build();
  return w;
}

}  // namespace dammloam::sim
