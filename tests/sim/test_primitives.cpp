#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "tools/simulate/path.hpp"
#include "tools/simulate/primitives.hpp"
#include "tools/simulate/scenes.hpp"

namespace dammloam::sim {
namespace {

constexpr double kPi = std::numbers::pi;

Ray MakeRay(Eigen::Vector3d origin, Eigen::Vector3d dir) { return {origin, dir.normalized()}; }

Hit Far() {
  Hit h;
  h.t = 1e9;
  return h;
}

TEST(Primitives, RectangleHitInsideAndMissOutside) {
  const Rectangle wall{{5, 0, 1}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                       Eigen::Vector3d::UnitZ(), 2.0, 1.0, 0.5f};
  Hit h = Far();
  ASSERT_TRUE(wall.Intersect(MakeRay({0, 0, 1}, {1, 0.2, 0}), 0.0, h));
  EXPECT_NEAR(h.t, std::hypot(5.0, 1.0), 1e-12);
  h = Far();
  EXPECT_FALSE(wall.Intersect(MakeRay({0, 0, 1}, {1, 0.5, 0}), 0.0, h));  // y = 2.5 > 2
  h = Far();
  EXPECT_FALSE(wall.Intersect(MakeRay({0, 0, 1}, {-1, 0, 0}), 0.0, h));  // behind
}

TEST(Primitives, NearestHitWins) {
  const Sphere a{{10, 0, 0}, 1.0, 0.1f}, b{{5, 0, 0}, 1.0, 0.9f};
  const Ray ray = MakeRay({0, 0, 0}, {1, 0, 0});
  Hit h = Far();
  EXPECT_TRUE(a.Intersect(ray, 0.0, h));
  EXPECT_TRUE(b.Intersect(ray, 0.0, h));
  EXPECT_FALSE(a.Intersect(ray, 0.0, h));  // farther than the current best
  EXPECT_NEAR(h.t, 4.0, 1e-12);
  EXPECT_FLOAT_EQ(h.reflectivity, 0.9f);
  EXPECT_NEAR(h.normal.x(), -1.0, 1e-12);
}

TEST(Primitives, OrientedBoxMatchesRotatedGeometry) {
  Box box{{10, 0, 0}, {1, 1, 1}, Eigen::Matrix3d::Identity(), 0.5f};
  box.rotation = Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Hit h = Far();
  ASSERT_TRUE(box.Intersect(MakeRay({0, 0, 0}, {1, 0, 0}), 0.0, h));
  EXPECT_NEAR(h.t, 10.0 - std::sqrt(2.0), 1e-12);  // the rotated corner points at the sensor
  // Axis-aligned: face at x = 9 with normal along x.
  box.rotation.setIdentity();
  h = Far();
  ASSERT_TRUE(box.Intersect(MakeRay({0, 0.5, 0.5}, {1, 0, 0}), 0.0, h));
  EXPECT_NEAR(h.t, 9.0, 1e-12);
  EXPECT_NEAR(std::abs(h.normal.x()), 1.0, 1e-12);
}

TEST(Primitives, CylinderSideAndTopCap) {
  const Cylinder trunk{{4, 0}, 0.5, 0.0, 3.0, 0.4f};
  Hit h = Far();
  ASSERT_TRUE(trunk.Intersect(MakeRay({0, 0, 1}, {1, 0, 0}), 0.0, h));
  EXPECT_NEAR(h.t, 3.5, 1e-12);
  h = Far();
  EXPECT_FALSE(trunk.Intersect(MakeRay({0, 0, 4}, {1, 0, 0}), 0.0, h));  // above the top
  h = Far();
  ASSERT_TRUE(trunk.Intersect(MakeRay({4, 0, 5}, {0, 0, -1}), 0.0, h));  // straight down
  EXPECT_NEAR(h.t, 2.0, 1e-12);
}

TEST(Primitives, HeightfieldHitLiesOnTheSurface) {
  const Heightfield ground(0.0, {{0.12, {0.25, 0.1}, 0.3}, {0.05, {-0.15, 0.57}, 1.7}});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-0.6, -0.01), azimuth(-kPi, kPi);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const double el = angle(rng), az = azimuth(rng);
    const Ray ray = MakeRay({1, 2, 1.8}, {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                          std::sin(el)});
    Hit h = Far();
    if (!ground.Intersect(ray, 0.0, h)) continue;
    ++hits;
    const Eigen::Vector3d p = ray.origin + h.t * ray.dir;
    ASSERT_NEAR(p.z(), ground.Height(p.x(), p.y()), 1e-9) << "ray " << i;
    // First crossing: the ray stays above the ground before the hit.
    for (double s = 0.0; s < h.t; s += 0.05) {
      const Eigen::Vector3d q = ray.origin + s * ray.dir;
      ASSERT_GT(q.z(), ground.Height(q.x(), q.y()) - 1e-9) << "ray " << i << " at " << s;
    }
  }
  EXPECT_EQ(hits, 2000);  // every downward ray from above an unbounded ground hits it
}

TEST(Path, ArcsAndLinesCloseTheLoop) {
  Path loop;
  for (int i = 0; i < 2; ++i) loop.Line(28).Arc(6, kPi / 2).Line(18).Arc(6, kPi / 2);
  EXPECT_NEAR(loop.length(), 2 * 28 + 2 * 18 + 2 * kPi * 6, 1e-9);
  const Path::State end = loop.At(loop.length());
  EXPECT_LT(end.position.norm(), 1e-9);
  EXPECT_NEAR(end.heading, 2 * kPi, 1e-9);
  const Path::State corner = loop.At(28 + 1.5 * kPi);  // halfway round the first corner
  EXPECT_NEAR(corner.position.x(), 28 + 6 * std::sin(kPi / 4), 1e-9);
  EXPECT_NEAR(corner.position.y(), 6 - 6 * std::cos(kPi / 4), 1e-9);
  EXPECT_NEAR(loop.At(loop.length() + 5.0, true).position.x(), 5.0, 1e-9);
}

// The grid must return exactly what testing every primitive would.
void ExpectGridMatchesBruteForce(SceneKind kind, Eigen::Vector3d origin) {
  const World world = BuildWorld(kind, 0.0, 30.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> el(-0.45, 0.45), az(-kPi, kPi);
  int hits = 0;
  for (int i = 0; i < 8000; ++i) {
    const double e = el(rng), a = az(rng);
    const Ray ray = MakeRay(origin, {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)});
    Hit brute = Far();
    brute.t = 120.0;
    bool any = false;
    for (const Primitive& p : world.scene.primitives()) {
      any |= std::visit([&](const auto& s) { return s.Intersect(ray, 1e-6, brute); }, p);
    }
    if (world.scene.ground()) any |= world.scene.ground()->Intersect(ray, 1e-6, brute);
    const std::optional<Hit> fast = world.scene.Cast(ray, 1e-6, 120.0);
    ASSERT_EQ(fast.has_value(), any) << SceneName(kind) << " ray " << i;
    if (any) {
      ++hits;
      ASSERT_NEAR(fast->t, brute.t, 1e-9) << SceneName(kind) << " ray " << i;
    }
  }
  EXPECT_GT(hits, 4000);
}

TEST(Scene, GridMatchesBruteForceOutdoor) { ExpectGridMatchesBruteForce(SceneKind::Outdoor, {3, 1, 1.9}); }
TEST(Scene, GridMatchesBruteForceZigzag) { ExpectGridMatchesBruteForce(SceneKind::Zigzag, {12, 0.5, 1.2}); }
TEST(Scene, GridMatchesBruteForceRepetitive) {
  ExpectGridMatchesBruteForce(SceneKind::Repetitive, {7, -0.2, 1.2});
}

// The plain corridors' door recesses are as deep as asked: a ray from the axis into a door at
// the straight corridor's x = 13.7 (left wall, y = +1.2) ends on the door, 1.2 m + depth away;
// beside it, on the wall.
TEST(Scene, RecessDepthSetsHowFarTheDoorSits) {
  for (const double depth : {kShallowRecess, 0.3}) {
    const World world = BuildWorld(SceneKind::StraightCorridor, 0.0, 60.0, depth);
    const auto door = world.scene.Cast(MakeRay({13.7, 0.0, 1.0}, {0.0, 1.0, 0.0}), 1e-6, 10.0);
    const auto wall = world.scene.Cast(MakeRay({11.0, 0.0, 1.0}, {0.0, 1.0, 0.0}), 1e-6, 10.0);
    ASSERT_TRUE(door.has_value());
    ASSERT_TRUE(wall.has_value());
    EXPECT_NEAR(door->t, 1.2 + depth, 1e-9) << depth;
    EXPECT_NEAR(wall->t, 1.2, 1e-9) << depth;
  }
}

TEST(Scene, NamesRoundTrip) {
  for (const std::string& name : SceneNames()) {
    const auto kind = ParseSceneKind(name);
    ASSERT_TRUE(kind.has_value()) << name;
    EXPECT_EQ(SceneName(*kind), name);
  }
  EXPECT_FALSE(ParseSceneKind("nope").has_value());
}

}  // namespace
}  // namespace dammloam::sim
