#include "tools/simulate/scenes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace dammloam::sim {

namespace {

constexpr double kPi = std::numbers::pi;

// Reflectivities: distinct per material so intensity images carry some texture.
constexpr float kFloor = 0.3f, kCeiling = 0.6f, kWall = 0.5f, kDoor = 0.2f, kPillar = 0.7f;

Rectangle HorizontalRect(double x0, double x1, double y0, double y1, double z, float refl) {
  return {{0.5 * (x0 + x1), 0.5 * (y0 + y1), z}, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
          Eigen::Vector3d::UnitY(), 0.5 * (x1 - x0), 0.5 * (y1 - y0), refl};
}

// Wall in a plane y = const, spanning x0..x1 and z0..z1.
Rectangle WallAlongX(double x0, double x1, double y, double z0, double z1, float refl) {
  return {{0.5 * (x0 + x1), y, 0.5 * (z0 + z1)}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(),
          Eigen::Vector3d::UnitZ(), 0.5 * (x1 - x0), 0.5 * (z1 - z0), refl};
}

// Wall in a plane x = const, spanning y0..y1 and z0..z1.
Rectangle WallAlongY(double y0, double y1, double x, double z0, double z1, float refl) {
  return {{x, 0.5 * (y0 + y1), 0.5 * (z0 + z1)}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
          Eigen::Vector3d::UnitZ(), 0.5 * (y1 - y0), 0.5 * (z1 - z0), refl};
}

Box AxisBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max, float refl) {
  return {0.5 * (min + max), 0.5 * (max - min), Eigen::Matrix3d::Identity(), refl};
}

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

void AddFloorAndCeiling(Scene& scene, const CorridorShape& c, double extra_width) {
  const double half = 0.5 * c.width + extra_width;
  scene.Add(HorizontalRect(c.x0, c.x1, -half, half, 0.0, kFloor));
  scene.Add(HorizontalRect(c.x0, c.x1, -half, half, c.height, kCeiling));
}

// One side wall with its door recesses (gap, lintel, jambs, recess back and top).
void AddSideWall(Scene& scene, const CorridorShape& c, int side, std::vector<double> doors) {
  const double y = side * 0.5 * c.width, y_back = side * (0.5 * c.width + kDoorDepth);
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
  AddSideWall(w.scene, c, +1, {});
  AddSideWall(w.scene, c, -1, {});
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
  AddSideWall(w.scene, c, +1, doors[0]);
  AddSideWall(w.scene, c, -1, doors[1]);
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
  AddSideWall(w.scene, c, +1, doors);
  AddSideWall(w.scene, c, -1, {});
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

  constexpr float kFacade = 0.55f, kTrunk = 0.35f, kCrown = 0.15f, kPole = 0.8f;
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
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (double s = 2.0; s < road.length(); s += 5.0 + 6.0 * uniform(rng)) {
    const Path::State st = road.At(s);
    const Eigen::Vector2d left(-std::sin(st.heading), std::cos(st.heading));
    const double side = uniform(rng) < 0.5 ? 1.0 : -1.0;
    const Eigen::Vector2d xy = st.position + side * (3.0 + 1.5 * uniform(rng)) * left;
    if (uniform(rng) < 0.2) {
      w.scene.Add(Cylinder{xy, 0.08, -1.0, 5.0, kPole});
      continue;
    }
    const double trunk_r = 0.15 + 0.15 * uniform(rng), trunk_h = 2.2 + 1.3 * uniform(rng);
    const double crown_r = 1.2 + 1.0 * uniform(rng);
    w.scene.Add(Cylinder{xy, trunk_r, -1.0, trunk_h, kTrunk});
    w.scene.Add(Sphere{Eigen::Vector3d(xy.x(), xy.y(), trunk_h + 0.8 * crown_r), crown_r, kCrown});
  }
  w.motion.path = road;
  w.motion.closed = true;
  w.motion.speed = speed;
  w.motion.sensor_height = 1.8;
  w.motion.ground = w.scene.ground();
  w.motion.wobble.lateral = 0.1;
  return w;
}

}  // namespace

std::vector<std::string> SceneNames() {
  return {"corridor", "zigzag", "outdoor", "repetitive", "corridor-return"};
}

std::optional<SceneKind> ParseSceneKind(std::string_view name) {
  if (name == "corridor") return SceneKind::Corridor;
  if (name == "zigzag") return SceneKind::Zigzag;
  if (name == "outdoor") return SceneKind::Outdoor;
  if (name == "repetitive") return SceneKind::Repetitive;
  if (name == "corridor-return") return SceneKind::CorridorReturn;
  return std::nullopt;
}

std::string_view SceneName(SceneKind kind) {
  switch (kind) {
    case SceneKind::Corridor: return "corridor";
    case SceneKind::Zigzag: return "zigzag";
    case SceneKind::Outdoor: return "outdoor";
    case SceneKind::Repetitive: return "repetitive";
    case SceneKind::CorridorReturn: return "corridor-return";
  }
  return "unknown";
}

double DefaultSpeed(SceneKind kind) { return kind == SceneKind::Outdoor ? 1.5 : 1.0; }

World BuildWorld(SceneKind kind, double speed, double duration) {
  if (!(speed > 0.0)) speed = DefaultSpeed(kind);
  duration = std::max(duration, 0.0);
  World w;
  switch (kind) {
    case SceneKind::Corridor: w = Corridor(speed, duration, false); break;
    case SceneKind::Zigzag: w = Zigzag(speed, duration); break;
    case SceneKind::Outdoor: w = Outdoor(speed); break;
    case SceneKind::Repetitive: w = Repetitive(speed, duration); break;
    case SceneKind::CorridorReturn: w = Corridor(speed, duration, true); break;
  }
  w.scene.Build();
  return w;
}

}  // namespace dammloam::sim
