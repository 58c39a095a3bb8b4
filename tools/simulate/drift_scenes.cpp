#include "tools/simulate/drift_scenes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "tools/simulate/angles.hpp"
#include "tools/simulate/scene_parts.hpp"

namespace dammloam::sim {

namespace {

// A fixed layout stream per scene: the layout never depends on the run's seed.
class Layout {
 public:
  explicit Layout(unsigned seed) : rng_(seed) {}
  double Range(double a, double b) { return a + (b - a) * uniform_(rng_); }
  bool Chance(double p) { return uniform_(rng_) < p; }

 private:
  std::mt19937 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// Wraps an angle into (-pi, pi].
double WrapAngle(double a) {
  while (a > kPi) a -= 2.0 * kPi;
  while (a <= -kPi) a += 2.0 * kPi;
  return a;
}

// --- campus-long ----------------------------------------------------------------------------

constexpr double kBlockX = 85.0, kBlockY = 65.0;  // street pitch
constexpr int kNodesX = 4, kNodesY = 3;           // streets x = 0..255, y = 0..130
constexpr double kSetback = 9.0;                  // buildings from a street's centreline
constexpr double kJunctionClear = 12.0;           // no tree or car this close to a crossing

using GridNode = std::array<int, 2>;

Eigen::Vector2d NodePosition(const GridNode& n) { return {n[0] * kBlockX, n[1] * kBlockY}; }

// Straight streets between grid nodes with corners of `radius`; the last leg is cut to
// `last_leg` metres. Consecutive legs must not turn back (no U-turns).
Path GridRoute(const std::vector<GridNode>& nodes, double radius, double last_leg) {
  std::vector<Eigen::Vector2d> legs;
  for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
    legs.push_back(NodePosition(nodes[k + 1]) - NodePosition(nodes[k]));
  }
  auto heading = [&](std::size_t k) { return std::atan2(legs[k].y(), legs[k].x()); };
  Path path({NodePosition(nodes.front()), heading(0)});
  double cut_in = 0.0;
  for (std::size_t k = 0; k < legs.size(); ++k) {
    const bool last = k + 1 == legs.size();
    const double turn = last ? 0.0 : WrapAngle(heading(k + 1) - heading(k));
    const double cut_out = std::abs(turn) > 1e-6 ? radius : 0.0;
    const double length = last ? last_leg : legs[k].norm();
    path.Line(length - cut_in - cut_out);
    if (cut_out > 0.0) path.Arc(radius, turn);
    cut_in = cut_out;
  }
  return path;
}

// The walk: round the southern blocks, north, back east and south through the middle (the
// southern street against its first direction), up the middle street, along the northern one
// again, down the eastern street against its first direction and west along the first street.
const std::vector<GridNode>& CampusRouteNodes() {
  static const std::vector<GridNode> nodes = {{0, 0}, {3, 0}, {3, 1}, {0, 1}, {0, 2}, {2, 2},
                                              {2, 0}, {1, 0}, {1, 2}, {3, 2}, {3, 0}, {1, 0}};
  return nodes;
}
constexpr double kCampusLastLeg = 110.0;  // of the final 170 m leg (3,0) -> (1,0)

Heightfield RollingGround() {
  // A long gentle hill (slopes up to ~2 %), mid-size swells and the campus scene's bumps.
  return Heightfield(0.0,
                     {{1.2, Eigen::Vector2d(2 * kPi / 420.0, 2 * kPi / 330.0), 0.3},
                      {0.25, Eigen::Vector2d(-2 * kPi / 75.0, 2 * kPi / 55.0), 1.7},
                      {0.06, Eigen::Vector2d(2 * kPi / 13.0, 2 * kPi / 17.0), 2.1},
                      {0.02, Eigen::Vector2d(2 * kPi / 6.3, 2 * kPi / 9.0), 0.9}},
                     0.25f);
}

class CampusBuilder {
 public:
  CampusBuilder(Scene& scene, const Heightfield& ground) : scene_(scene), ground_(ground), layout_(53) {}

  void Building(double x0, double y0, double x1, double y1) {
    const double z = ground_.Height(0.5 * (x0 + x1), 0.5 * (y0 + y1));
    Box b = AxisBox({x0, y0, z - 3.0}, {x1, y1, z + layout_.Range(5.0, 18.0)}, kFacade);
    b.rotation = Eigen::AngleAxisd(layout_.Range(-5.0, 5.0) * kDegToRad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    scene_.Add(b);
  }

  // A row of buildings along x (x0..x1), their near side at y_near, extending towards `away`.
  void RowX(double x0, double x1, double y_near, int away) {
    for (double x = x0 + layout_.Range(0.0, 4.0); x < x1;) {
      const double width = std::min(layout_.Range(8.0, 18.0), x1 - x), depth = layout_.Range(6.0, 12.0);
      if (width > 4.0 && layout_.Chance(0.8)) {
        Building(x, away > 0 ? y_near : y_near - depth, x + width, away > 0 ? y_near + depth : y_near);
      }
      x += width + layout_.Range(3.0, 9.0);
    }
  }
  void RowY(double y0, double y1, double x_near, int away) {
    for (double y = y0 + layout_.Range(0.0, 4.0); y < y1;) {
      const double width = std::min(layout_.Range(8.0, 18.0), y1 - y), depth = layout_.Range(6.0, 12.0);
      if (width > 4.0 && layout_.Chance(0.8)) {
        Building(away > 0 ? x_near : x_near - depth, y, away > 0 ? x_near + depth : x_near, y + width);
      }
      y += width + layout_.Range(3.0, 9.0);
    }
  }

  // Buildings along the four sides of block (i, j), or a park of scattered trees.
  void Block(int i, int j, bool park) {
    const double x0 = i * kBlockX + kSetback, x1 = (i + 1) * kBlockX - kSetback;
    const double y0 = j * kBlockY + kSetback, y1 = (j + 1) * kBlockY - kSetback;
    if (park) {
      for (int k = 0; k < 14; ++k) Tree({layout_.Range(x0 + 2.0, x1 - 2.0), layout_.Range(y0 + 2.0, y1 - 2.0)});
      return;
    }
    RowX(x0, x1, y0, +1);
    RowX(x0, x1, y1, -1);
    RowY(y0 + 12.0, y1 - 12.0, x0, +1);
    RowY(y0 + 12.0, y1 - 12.0, x1, -1);
  }

  void Tree(const Eigen::Vector2d& xy) {
    const double z = ground_.Height(xy.x(), xy.y());
    const double trunk_r = layout_.Range(0.15, 0.3), trunk_h = layout_.Range(2.2, 3.5);
    const double crown_r = layout_.Range(1.2, 2.2);
    scene_.Add(Cylinder{xy, trunk_r, z - 1.0, z + trunk_h, kTrunk});
    scene_.Add(Sphere{Eigen::Vector3d(xy.x(), xy.y(), z + trunk_h + 0.8 * crown_r), crown_r, kCrown});
  }

  // Trees and poles on the pavements (4.5-6 m from the centreline) and parked cars (centre
  // 2.8 m out) along one straight street, none near a crossing.
  void Street(const Eigen::Vector2d& start, double heading, double length, double node_pitch) {
    const Eigen::Vector2d forward(std::cos(heading), std::sin(heading)), left = LeftOf(heading);
    auto near_junction = [&](double s) {
      const double to_node = std::fmod(s, node_pitch);
      return std::min(to_node, node_pitch - to_node) < kJunctionClear;
    };
    for (double s = 2.0; s < length; s += layout_.Range(6.0, 14.0)) {
      if (near_junction(s)) continue;
      const double side = layout_.Chance(0.5) ? 1.0 : -1.0;
      const Eigen::Vector2d xy = start + s * forward + side * layout_.Range(4.5, 6.0) * left;
      if (layout_.Chance(0.25)) {
        const double z = ground_.Height(xy.x(), xy.y());
        scene_.Add(Cylinder{xy, 0.08, z - 1.0, z + 5.0, kPole});
      } else {
        Tree(xy);
      }
    }
    for (double s = 3.0; s + 3.0 < length; s += 6.0) {
      if (near_junction(s) || near_junction(s + 5.0) || !layout_.Chance(0.3)) continue;
      const double side = layout_.Chance(0.5) ? 1.0 : -1.0;
      Car(start + (s + 2.5) * forward + side * 2.8 * left, heading);
    }
  }

  void Car(const Eigen::Vector2d& xy, double heading) {
    static constexpr float kCarPaint = 0.45f;
    const double z = ground_.Height(xy.x(), xy.y());
    Box car = AxisBox({-2.25, -0.9, -0.15}, {2.25, 0.9, 1.5}, kCarPaint);
    car.center = Eigen::Vector3d(xy.x(), xy.y(), z + 0.675);
    car.rotation = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    scene_.Add(car);
  }

 private:
  Scene& scene_;
  const Heightfield& ground_;
  Layout layout_;
};

// --- two-floor ------------------------------------------------------------------------------

constexpr double kStorey = kTwoFloorStorey, kRoomHeight = 2.8;
// The ring corridor's centreline (x 3..43, y 3..21) and its walls 1.2 m either side.
constexpr double kRingX0 = 3.0, kRingX1 = 43.0, kRingY0 = 3.0, kRingY1 = 21.0, kHalfWidth = 1.2;
// The stairwell opens off the southern corridor into the core: the flight climbs north at
// x 18..19.4, a landing at the top, the walkway back south at x 19.4..20.8 on floor 2.
constexpr double kWellX0 = 18.0, kWellXMid = 19.4, kWellX1 = 20.8;
constexpr double kWellY0 = kRingY0 + kHalfWidth, kWellY1 = 11.5;
constexpr int kSteps = 18;
constexpr double kTread = 0.28, kFlightY0 = 4.4;
constexpr double kFlightY1 = kFlightY0 + kSteps * kTread;  // 9.44: floor 2's landing

// One straight wall of a corridor, with the direction into the corridor.
struct CorridorWall {
  bool along_x = true;  // the wall lies in a plane y = c (else x = c)
  double c = 0.0;
  double from = 0.0, to = 0.0;
  double into = 1.0;  // +1 / -1: the corridor lies on the +c / -c side
};

// A box against a wall: `u` along it, `v` out from it into the corridor, z absolute.
Box WallBox(const CorridorWall& w, double u0, double u1, double v0, double v1, double z0, double z1, float refl) {
  const double a = w.c + w.into * v0, b = w.c + w.into * v1;
  const double lo = std::min(a, b), hi = std::max(a, b);
  return w.along_x ? AxisBox({u0, lo, z0}, {u1, hi, z1}, refl) : AxisBox({lo, u0, z0}, {hi, u1, z1}, refl);
}

Rectangle WallPiece(const CorridorWall& w, double u0, double u1, double z0, double z1) {
  return w.along_x ? WallAlongX(u0, u1, w.c, z0, z1, kWall) : WallAlongY(u0, u1, w.c, z0, z1, kWall);
}

// Something standing against a corridor wall, drawn once and built on both floors.
struct WallFeature {
  enum Kind { Pillar, Door, Radiator, Cabinet } kind = Pillar;
  double u = 0.0;  // centre along the wall
};

std::vector<CorridorWall> RingWalls() {
  const double xo0 = kRingX0 - kHalfWidth, xo1 = kRingX1 + kHalfWidth;
  const double yo0 = kRingY0 - kHalfWidth, yo1 = kRingY1 + kHalfWidth;
  const double xi0 = kRingX0 + kHalfWidth, xi1 = kRingX1 - kHalfWidth;
  const double yi0 = kRingY0 + kHalfWidth, yi1 = kRingY1 - kHalfWidth;
  return {{true, yo0, xo0, xo1, +1}, {true, yo1, xo0, xo1, -1}, {false, xo0, yo0, yo1, +1},
          {false, xo1, yo0, yo1, -1}, {true, yi0, xi0, xi1, -1}, {true, yi1, xi0, xi1, +1},
          {false, xi0, yi0, yi1, -1}, {false, xi1, yi0, yi1, +1}};
}

// Irregularly spaced features along each wall (fixed layout seed), kept 1.5 m from the ends
// and clear of the stairwell's doorways on the inner southern wall.
std::vector<std::vector<WallFeature>> DrawWallFeatures(const std::vector<CorridorWall>& walls) {
  Layout layout(71);
  std::vector<std::vector<WallFeature>> features(walls.size());
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const CorridorWall& w = walls[i];
    const bool stair_wall = w.along_x && w.c == kWellY0;
    for (double u = w.from + layout.Range(1.5, 4.0); u < w.to - 1.5; u += layout.Range(3.0, 8.0)) {
      if (stair_wall && u > kWellX0 - 1.5 && u < kWellX1 + 1.5) continue;
      const double pick = layout.Range(0.0, 1.0);
      const WallFeature::Kind kind = pick < 0.3   ? WallFeature::Pillar
                                     : pick < 0.7 ? WallFeature::Door
                                     : pick < 0.85 ? WallFeature::Radiator
                                                   : WallFeature::Cabinet;
      features[i].push_back({kind, u});
    }
  }
  return features;
}

void AddWallFeature(Scene& scene, const CorridorWall& w, const WallFeature& f, double z) {
  const double u = f.u;
  switch (f.kind) {
    case WallFeature::Pillar:
      scene.Add(WallBox(w, u - 0.25, u + 0.25, 0.0, 0.3, z, z + kRoomHeight, kPillar));
      break;
    case WallFeature::Door:  // a leaf 3 cm proud of the wall in a frame 8 cm proud
      scene.Add(WallBox(w, u - 0.45, u + 0.45, 0.0, 0.03, z, z + 2.05, kDoor));
      scene.Add(WallBox(w, u - 0.55, u - 0.45, 0.0, 0.08, z, z + 2.15, kPillar));
      scene.Add(WallBox(w, u + 0.45, u + 0.55, 0.0, 0.08, z, z + 2.15, kPillar));
      scene.Add(WallBox(w, u - 0.55, u + 0.55, 0.0, 0.08, z + 2.05, z + 2.15, kPillar));
      break;
    case WallFeature::Radiator:
      scene.Add(WallBox(w, u - 0.6, u + 0.6, 0.02, 0.12, z + 0.15, z + 0.75, kPillar));
      break;
    case WallFeature::Cabinet:
      scene.Add(WallBox(w, u - 0.4, u + 0.4, 0.0, 0.45, z, z + 1.9, kDoor));
      break;
  }
}

// A horizontal slab over the whole building but for the stair's hole.
void AddSlabWithHole(Scene& scene, double z, float refl) {
  const double x0 = kRingX0 - kHalfWidth, x1 = kRingX1 + kHalfWidth;
  const double y0 = kRingY0 - kHalfWidth, y1 = kRingY1 + kHalfWidth;
  scene.Add(HorizontalRect(x0, kWellX0, y0, y1, z, refl));
  scene.Add(HorizontalRect(kWellXMid, x1, y0, y1, z, refl));
  scene.Add(HorizontalRect(kWellX0, kWellXMid, y0, kWellY0, z, refl));
  scene.Add(HorizontalRect(kWellX0, kWellXMid, kFlightY1, y1, z, refl));
}

// One floor's corridor walls: `door_x0..door_x1` is its opening into the stairwell.
void AddFloorWalls(Scene& scene, const std::vector<CorridorWall>& walls,
                   const std::vector<std::vector<WallFeature>>& features, double z, double door_x0,
                   double door_x1) {
  const double z0 = z - (kStorey - kRoomHeight), z1 = z + kRoomHeight;  // up to the slab above
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const CorridorWall& w = walls[i];
    if (w.along_x && w.c == kWellY0) {
      scene.Add(WallPiece(w, w.from, door_x0, z0, z1));
      scene.Add(WallPiece(w, door_x0, door_x1, z + 2.1, z1));  // lintel
      scene.Add(WallPiece(w, door_x1, w.to, z0, z1));
    } else {
      scene.Add(WallPiece(w, w.from, w.to, z0, z1));
    }
    for (const WallFeature& f : features[i]) AddWallFeature(scene, w, f, z);
  }
  // Ceiling lamps along the centreline every 6 m.
  for (double x = kRingX0 + 2.0; x < kRingX1 - 1.0; x += 6.0) {
    for (const double y : {kRingY0, kRingY1}) scene.Add(AxisBox({x - 0.6, y - 0.15, z1 - 0.08}, {x + 0.6, y + 0.15, z1}, kPillar));
  }
  for (double y = kRingY0 + 5.0; y < kRingY1 - 2.0; y += 6.0) {
    for (const double x : {kRingX0, kRingX1}) scene.Add(AxisBox({x - 0.15, y - 0.6, z1 - 0.08}, {x + 0.15, y + 0.6, z1}, kPillar));
  }
}

void AddStairwell(Scene& scene) {
  const double top = kStorey + kRoomHeight;
  scene.Add(WallAlongY(kWellY0, kWellY1, kWellX0, 0.0, top, kWall));
  scene.Add(WallAlongY(kWellY0, kWellY1, kWellX1, 0.0, top, kWall));
  scene.Add(WallAlongX(kWellX0, kWellX1, kWellY1, 0.0, top, kWall));
  // Floor 1: the flight's side wall hides the space under the walkway; floor 2: a railing
  // between the hole and the walkway, and the slab's edge in between.
  scene.Add(WallAlongY(kWellY0, kFlightY1, kWellXMid, 0.0, kStorey, kWall));
  scene.Add(AxisBox({kWellXMid - 0.02, kWellY0, kStorey}, {kWellXMid + 0.02, kFlightY1, kStorey + 1.0}, kPillar));
  const double rise = kStorey / kSteps;
  for (int i = 0; i < kSteps; ++i) {
    const double y = kFlightY0 + i * kTread;
    scene.Add(AxisBox({kWellX0, y, 0.0}, {kWellXMid, y + kTread, (i + 1) * rise}, kFloor));
  }
}

// --- warehouse ------------------------------------------------------------------------------

constexpr int kAisles = kWarehouseAisles;
constexpr double kAislePitch = kWarehouseAislePitch, kAisleY0 = kWarehouseAisleY0;
constexpr double kRackDepth = 1.1, kRackX0 = kWarehouseRackX0, kBay = 2.5;
constexpr int kBays = 12;  // racks x 8..38
static_assert(kRackX0 + kBays * kBay == kWarehouseRackX1);
constexpr double kHallX = 46.0, kHallY = 29.0, kHallHeight = 10.0;
constexpr double kRackHeight = 6.0;
constexpr std::array<double, 3> kBeamLevels = {1.4, 2.8, 4.2};

double AisleY(int k) { return kAisleY0 + k * kAislePitch; }

// What stands on each shelf level of each bay (two pallet slots a level): one pattern for the
// racks facing +y and one for those facing -y, so every aisle (one of each on its sides) is
// the same aisle.
struct PalletPattern {
  // height of the load per [bay][level 0..3][slot 0..1], 0: empty
  std::array<std::array<std::array<double, 2>, 4>, kBays> load{};
};

PalletPattern DrawPallets(Layout& layout) {
  PalletPattern p;
  for (auto& bay : p.load) {
    for (auto& level : bay) {
      for (double& slot : level) slot = layout.Chance(0.6) ? layout.Range(0.8, 1.25) : 0.0;
    }
  }
  return p;
}

// A single rack row between y_back and the aisle face at y_face (either order).
void AddRack(Scene& scene, double y_face, double y_back, const PalletPattern& pallets) {
  constexpr float kSteel = 0.6f, kLoad = 0.4f;
  const double into = y_back > y_face ? 1.0 : -1.0;  // from the face towards the back
  for (const double y : {y_face + into * 0.05, y_back - into * 0.05}) {
    for (int m = 0; m <= kBays; ++m) {
      const double x = kRackX0 + m * kBay;
      scene.Add(AxisBox({x - 0.05, y - 0.05, 0.0}, {x + 0.05, y + 0.05, kRackHeight}, kSteel));
    }
    for (int m = 0; m < kBays; ++m) {
      const double x = kRackX0 + m * kBay;
      for (const double z : kBeamLevels) {
        scene.Add(AxisBox({x + 0.05, y - 0.025, z - 0.12}, {x + kBay - 0.05, y + 0.025, z}, kSteel));
      }
    }
  }
  const double y_lo = std::min(y_face, y_back) + 0.05, y_hi = std::max(y_face, y_back) - 0.05;
  for (int m = 0; m < kBays; ++m) {
    for (int level = 0; level < 4; ++level) {
      const double z = level == 0 ? 0.0 : kBeamLevels[static_cast<std::size_t>(level - 1)];
      for (int slot = 0; slot < 2; ++slot) {
        const double h = pallets.load[static_cast<std::size_t>(m)][static_cast<std::size_t>(level)]
                                     [static_cast<std::size_t>(slot)];
        if (h <= 0.0) continue;
        const double x = kRackX0 + m * kBay + 0.12 + slot * 1.16;
        scene.Add(AxisBox({x, y_lo, z}, {x + 1.1, y_hi, z + std::min(h, 1.25)}, kLoad));
      }
    }
  }
}

void AddHall(Scene& scene) {
  constexpr float kConcrete = 0.35f;
  scene.Add(HorizontalRect(0.0, kHallX, 0.0, kHallY, 0.0, kFloor));
  scene.Add(HorizontalRect(0.0, kHallX, 0.0, kHallY, kHallHeight, kCeiling));
  scene.Add(WallAlongY(0.0, kHallY, 0.0, 0.0, kHallHeight, kConcrete));
  scene.Add(WallAlongY(0.0, kHallY, kHallX, 0.0, kHallHeight, kConcrete));
  scene.Add(WallAlongX(0.0, kHallX, 0.0, 0.0, kHallHeight, kConcrete));
  scene.Add(WallAlongX(0.0, kHallX, kHallY, 0.0, kHallHeight, kConcrete));
  // What tells the aisles' ends apart: dock doors (recessed shutters) in the east wall, a
  // site office in the north-west corner, the hall's columns along the walls.
  for (const double y : {4.5, 12.8, 23.6}) scene.Add(AxisBox({kHallX - 0.3, y - 1.5, 0.0}, {kHallX, y + 1.5, 3.5}, kDoor));
  scene.Add(AxisBox({0.0, 20.0, 0.0}, {2.0, 27.0, 3.0}, kWall));
  for (double y = 2.0; y < kHallY; y += 8.1) {
    scene.Add(AxisBox({0.0, y - 0.2, 0.0}, {0.4, y + 0.2, kHallHeight}, kPillar));
    scene.Add(AxisBox({kHallX - 0.4, y + 1.7, 0.0}, {kHallX, y + 2.1, kHallHeight}, kPillar));
  }
  // Lamps hanging over every aisle, the same in each.
  for (int k = 0; k < kAisles; ++k) {
    for (double x = kRackX0 + 2.0; x < kRackX0 + kBays * kBay; x += 5.0) {
      scene.Add(AxisBox({x - 0.6, AisleY(k) - 0.15, 7.5}, {x + 0.6, AisleY(k) + 0.15, 7.7}, kPillar));
    }
  }
}

// Up aisle 0, down 1, ... (U-turns in the cross aisles), then from the end of the last aisle
// back through aisle 2 against its first direction and aisle 0 in its first direction.
Path WarehouseRoute() {
  const double x_east = kRackX0 + kBays * kBay + 2.0, x_west = kRackX0 - 2.0;  // turn centres
  const double u_turn = 0.5 * kAislePitch;
  const double run = x_east - x_west;
  Path p({Eigen::Vector2d(x_west - 2.0, AisleY(0)), 0.0});
  p.Line(run + 2.0);
  for (int k = 1; k < kAisles; ++k) {
    p.Arc(u_turn, k % 2 == 1 ? kPi : -kPi);
    p.Line(run);
  }
  // Now at the east end of the last aisle, heading +x: south along the east cross aisle.
  constexpr double kCorner = 2.0;
  p.Line(0.5).Arc(kCorner, -kPi / 2);
  p.Line((AisleY(kAisles - 1) - AisleY(2)) - 2.0 * kCorner).Arc(kCorner, -kPi / 2);  // into aisle 2, heading -x
  p.Line(run + 0.5 - 2.0 * kCorner + 2.0).Arc(kCorner, kPi / 2);   // south along the west cross aisle
  p.Line((AisleY(2) - AisleY(0)) - 2.0 * kCorner).Arc(kCorner, kPi / 2);  // into aisle 0, heading +x
  p.Line(0.5 * run);
  return p;
}

}  // namespace

World CampusLong(double speed, double arrive_time) {
  World w;
  w.scene.SetGround(RollingGround());
  const Heightfield& ground = *w.scene.ground();
  CampusBuilder build(w.scene, ground);
  // Block (2, 0) is a park and the south-east outside is an open field: the eastern part of the
  // first street and the eastern street have little but trees and poles beside them.
  for (int i = 0; i + 1 < kNodesX; ++i) {
    for (int j = 0; j + 1 < kNodesY; ++j) build.Block(i, j, i == 2 && j == 0);
  }
  const double x_max = (kNodesX - 1) * kBlockX, y_max = (kNodesY - 1) * kBlockY;
  build.RowX(-30.0, 2.0 * kBlockX - 20.0, -kSetback, -1);           // south, west part only
  build.RowX(-30.0, x_max + 30.0, y_max + kSetback, +1);             // north
  build.RowY(-30.0, y_max + 30.0, -kSetback, -1);                    // west
  build.RowY(kBlockY + kSetback, y_max + 30.0, x_max + kSetback, +1);  // east, northern part
  for (int j = 0; j < kNodesY; ++j) build.Street({0.0, j * kBlockY}, 0.0, x_max, kBlockX);
  for (int i = 0; i < kNodesX; ++i) build.Street({i * kBlockX, 0.0}, kPi / 2, y_max, kBlockY);

  w.motion.path = GridRoute(CampusRouteNodes(), std::clamp(speed, 4.0, 10.0), kCampusLastLeg);
  w.motion.speed = speed;
  w.motion.sensor_height = 1.8;
  w.motion.ground = ground;
  w.motion.arrive_time = arrive_time;
  return w;
}

World TwoFloor(double arrive_time) {
  World w;
  const std::vector<CorridorWall> walls = RingWalls();
  const std::vector<std::vector<WallFeature>> features = DrawWallFeatures(walls);
  w.scene.Add(HorizontalRect(kRingX0 - kHalfWidth, kRingX1 + kHalfWidth, kRingY0 - kHalfWidth,
                             kRingY1 + kHalfWidth, 0.0, kFloor));
  AddSlabWithHole(w.scene, kRoomHeight, kCeiling);
  AddSlabWithHole(w.scene, kStorey, kFloor);
  w.scene.Add(HorizontalRect(kRingX0 - kHalfWidth, kRingX1 + kHalfWidth, kRingY0 - kHalfWidth,
                             kRingY1 + kHalfWidth, kStorey + kRoomHeight, kCeiling));
  AddFloorWalls(w.scene, walls, features, 0.0, kWellX0, kWellXMid);
  AddFloorWalls(w.scene, walls, features, kStorey, kWellXMid, kWellX1);
  AddStairwell(w.scene);

  // Floor 1 from x = 8 on the southern corridor, anticlockwise once round and on to the stair.
  constexpr double kCorner = 0.8, kIntoWell = 1.0, kTopTurn = 0.7;
  const double side_x = kRingX1 - kRingX0 - 2.0 * kCorner, side_y = kRingY1 - kRingY0 - 2.0 * kCorner;
  const double flight_x = 0.5 * (kWellX0 + kWellXMid), walkway_x = 0.5 * (kWellXMid + kWellX1);
  Path p({Eigen::Vector2d(8.0, kRingY0), 0.0});
  p.Line(kRingX1 - kCorner - 8.0).Arc(kCorner, kPi / 2).Line(side_y).Arc(kCorner, kPi / 2);
  p.Line(side_x).Arc(kCorner, kPi / 2).Line(side_y).Arc(kCorner, kPi / 2);
  p.Line(flight_x - kIntoWell - (kRingX0 + kCorner)).Arc(kIntoWell, kPi / 2);
  // Up the flight (from y = kRingY0 + kIntoWell), round on the landing, back down the walkway.
  const double flight_start = p.length() + (kFlightY0 - (kRingY0 + kIntoWell));
  const double up = kFlightY1 + 0.5 - (kRingY0 + kIntoWell);
  p.Line(up);
  const double flight_end = flight_start + (kFlightY1 - kFlightY0);
  p.Arc(kTopTurn, -kPi).Line(up).Arc(kIntoWell, kPi / 2);
  // Floor 2: once round, then on past the stair to x = 32.
  const double x_floor2 = walkway_x + kIntoWell;
  p.Line(kRingX1 - kCorner - x_floor2).Arc(kCorner, kPi / 2).Line(side_y).Arc(kCorner, kPi / 2);
  p.Line(side_x).Arc(kCorner, kPi / 2).Line(side_y).Arc(kCorner, kPi / 2);
  p.Line(32.0 - (kRingX0 + kCorner));
  w.motion.path = p;
  w.motion.floor_rises = {{flight_start, flight_end, kStorey}};
  w.motion.slow_zones = {{flight_start - 0.3, flight_end + 0.3, 0.45}};
  w.motion.speed = 1.0;
  w.motion.arrive_time = arrive_time;
  return w;
}

World Warehouse(double arrive_time) {
  World w;
  AddHall(w.scene);
  Layout layout(97);
  const PalletPattern facing_north = DrawPallets(layout), facing_south = DrawPallets(layout);
  // Rack faces 1.6 m either side of each aisle's centre; racks back to back between aisles.
  for (int k = 0; k < kAisles; ++k) {
    const double y = AisleY(k);
    AddRack(w.scene, y - 1.6, y - 1.6 - kRackDepth, facing_north);
    AddRack(w.scene, y + 1.6, y + 1.6 + kRackDepth, facing_south);
  }
  w.motion.path = WarehouseRoute();
  w.motion.speed = 1.0;
  w.motion.arrive_time = arrive_time;
  return w;
}

}  // namespace dammloam::sim
