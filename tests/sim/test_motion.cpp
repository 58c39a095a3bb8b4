// Realistic carriers (motion.hpp), the tunnel primitive, the new scenes and the presets.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {
namespace {

constexpr double kPi = std::numbers::pi;

// A carrier walking a long straight path for `duration` seconds (2000 scans at 10 Hz).
Trajectory StraightWalk(MotionKind kind, std::uint64_t seed, double duration = 200.0) {
  MotionSpec spec;
  spec.path = Path().Line(1000.0);
  spec.kind = kind;
  spec.seed = seed;
  spec.duration = duration;
  return Trajectory(spec);
}

double HorizontalSpeed(const Trajectory& traj, double t, double dt) {
  return (traj.Pose(t + dt).translation() - traj.Pose(t).translation()).head<2>().norm() / dt;
}

double StdDev(const std::vector<double>& v) {
  double mean = 0.0, sq = 0.0;
  for (const double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (const double x : v) sq += (x - mean) * (x - mean);
  return std::sqrt(sq / static_cast<double>(v.size()));
}

TEST(Motion, NamesRoundTrip) {
  for (const std::string& name : MotionNames()) {
    const auto kind = ParseMotionKind(name);
    ASSERT_TRUE(kind.has_value()) << name;
    EXPECT_EQ(MotionName(*kind), name);
  }
  EXPECT_FALSE(ParseMotionKind("flying").has_value());
}

TEST(Motion, HandheldSpeedVariesStopsAndShowsTheGait) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Trajectory walk = StraightWalk(MotionKind::Handheld, seed);
    ASSERT_NE(walk.carrier(), nullptr);
    // Per-scan speed (10 Hz, as the ground truth of a sequence gives it).
    std::vector<double> per_scan;
    double slowest_after_start = 1e9;
    for (int i = 0; i < 2000; ++i) {
      per_scan.push_back(HorizontalSpeed(walk, 0.1 * i, 0.1));
      if (i > 50) slowest_after_start = std::min(slowest_after_start, per_scan.back());
    }
    EXPECT_GT(StdDev(per_scan), 0.1) << "seed " << seed;
    EXPECT_LT(slowest_after_start, 0.05) << "seed " << seed << ": no stop";
    EXPECT_LT(*std::max_element(per_scan.begin(), per_scan.end()), 2.0);

    // Speed maxima per second while walking: the step frequency (1.8-2.0 Hz).
    constexpr double kDt = 0.01;
    std::vector<double> v;
    for (double t = 0.0; t < 200.0; t += kDt) v.push_back(HorizontalSpeed(walk, t, kDt));
    int maxima = 0;
    double walking = 0.0;
    for (std::size_t i = 1; i + 1 < v.size(); ++i) {
      if (v[i] < 0.8) continue;
      walking += kDt;
      if (v[i] > v[i - 1] && v[i] >= v[i + 1]) ++maxima;
    }
    ASSERT_GT(walking, 100.0) << "seed " << seed;
    const double rate = maxima / walking;
    EXPECT_GT(rate, 1.7) << "seed " << seed;
    EXPECT_LT(rate, 2.1) << "seed " << seed;
    EXPECT_GE(walk.carrier()->gait_hz(), 1.8);
    EXPECT_LE(walk.carrier()->gait_hz(), 2.0);
  }
}

// Every column is fired at its own time: positions must be continuous and so must velocities
// (no jump between consecutive 1 ms samples beyond what v_max and a_max allow).
TEST(Motion, PositionAndVelocityAreContinuous) {
  struct Case {
    MotionKind kind;
    double v_max, a_max;
  };
  for (const Case c : {Case{MotionKind::Handheld, 2.5, 10.0}, Case{MotionKind::Legged, 1.5, 10.0},
                       Case{MotionKind::Wheeled, 1.6, 200.0}}) {
    const Trajectory walk = StraightWalk(c.kind, 5, 120.0);
    constexpr double kDt = 0.001;
    Eigen::Vector3d before = walk.Pose(-kDt).translation(), now = walk.Pose(0.0).translation();
    double worst_step = 0.0, worst_second = 0.0;
    for (double t = kDt; t < 125.0; t += kDt) {
      const Eigen::Vector3d next = walk.Pose(t).translation();
      worst_step = std::max(worst_step, (next - now).norm());
      worst_second = std::max(worst_second, (next - 2.0 * now + before).norm());
      before = now;
      now = next;
    }
    EXPECT_LT(worst_step, c.v_max * kDt) << MotionName(c.kind);
    EXPECT_LT(worst_second, c.a_max * kDt * kDt) << MotionName(c.kind);
  }
}

TEST(Motion, StartsFromRestAndCurvesSlowItDown) {
  MotionSpec spec;
  spec.path = Path().Line(20.0).Arc(0.5, kPi).Line(20.0);
  spec.kind = MotionKind::Handheld;
  spec.duration = 60.0;
  const Trajectory walk(spec);
  EXPECT_LT(HorizontalSpeed(walk, 0.0, 0.01), 0.01);
  double slowest_on_turn = 1e9, fastest_on_turn = 0.0;
  for (double t = 0.0; t < 60.0; t += 0.01) {
    const double s = walk.carrier()->Eval(t).s;
    if (s > 20.2 && s < 21.4) {
      const double v = walk.carrier()->Eval(t).speed;
      slowest_on_turn = std::min(slowest_on_turn, v);
      fastest_on_turn = std::max(fastest_on_turn, v);
    }
  }
  EXPECT_GT(fastest_on_turn, 0.2);   // it does walk round
  EXPECT_LT(fastest_on_turn, 0.55);  // U-turn of r 0.5 m at ~0.4 m/s (+gait)
  // Open path: it stops at the end and stays there.
  const Eigen::Vector3d end = walk.Pose(59.0).translation(), later = walk.Pose(80.0).translation();
  EXPECT_LT((end - later).norm(), 1e-6);
  EXPECT_NEAR(walk.carrier()->Eval(80.0).s, spec.path.length(), 0.02);
}

TEST(Motion, SameSeedSameTrajectoryOtherSeedDiffers) {
  for (const MotionKind kind : {MotionKind::Handheld, MotionKind::Legged, MotionKind::Wheeled}) {
    const Trajectory a = StraightWalk(kind, 7, 60.0), b = StraightWalk(kind, 7, 60.0);
    const Trajectory c = StraightWalk(kind, 8, 60.0);
    double same = 0.0, differ = 0.0;
    for (double t = 0.0; t < 60.0; t += 0.37) {
      const Eigen::Isometry3d pa = a.Pose(t), pb = b.Pose(t), pc = c.Pose(t);
      same = std::max(same, (pa.matrix() - pb.matrix()).norm());
      differ = std::max(differ, (pa.translation() - pc.translation()).norm());
    }
    EXPECT_EQ(same, 0.0) << MotionName(kind);
    EXPECT_GT(differ, 0.5) << MotionName(kind);
  }
}

TEST(Motion, PoseIsCheap) {
  const Trajectory walk = StraightWalk(MotionKind::Handheld, 1, 200.0);
  const auto start = std::chrono::steady_clock::now();
  double sink = 0.0;
  constexpr int kCalls = 200000;
  for (int i = 0; i < kCalls; ++i) sink += walk.Pose(i * 0.001).translation().x();
  const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  // Informational (speed is measured in benchmarks, not asserted here).
  std::printf("Pose(t): %.3f us per call (sink %.1f)\n", us / kCalls, sink);
  EXPECT_TRUE(std::isfinite(sink));
}

// --- The tunnel primitive -----------------------------------------------------------------

Ray MakeRay(Eigen::Vector3d origin, Eigen::Vector3d dir) { return {origin, dir.normalized()}; }
Hit Far() {
  Hit h;
  h.t = 1e9;
  return h;
}

TEST(CylinderX, InsideSurfaceGivesTheTunnelDistance) {
  const CylinderX tunnel{{0.0, 1.1}, 2.6, 0.0, 120.0, true, 0.0, 0.35f};
  Hit h = Far();
  ASSERT_TRUE(tunnel.Intersect(MakeRay({5, 0, 1.1}, {0, 1, 0}), 0.0, h));  // from the axis
  EXPECT_NEAR(h.t, 2.6, 1e-12);
  EXPECT_NEAR(std::abs(h.normal.y()), 1.0, 1e-12);
  h = Far();
  ASSERT_TRUE(tunnel.Intersect(MakeRay({5, 0, 1.1}, {3, 1, 1}), 0.0, h));  // any direction
  EXPECT_NEAR(h.t * std::sqrt(2.0 / 11.0), 2.6, 1e-12);  // the y-z part of the ray is 2.6 long
  h = Far();
  ASSERT_TRUE(tunnel.Intersect(MakeRay({5, 0.4, 0.6}, {0, 0, 1}), 0.0, h));  // off the axis, up
  EXPECT_NEAR(h.t, 1.1 + std::sqrt(2.6 * 2.6 - 0.16) - 0.6, 1e-12);
  h = Far();
  EXPECT_FALSE(tunnel.Intersect(MakeRay({5, 0, 1.1}, {0, 0, -1}), 0.0, h));  // below the floor
  h = Far();
  EXPECT_FALSE(tunnel.Intersect(MakeRay({118, 0, 1.1}, {1, 0.01, 0}), 0.0, h));  // out the end
  h = Far();
  EXPECT_FALSE(tunnel.Intersect(MakeRay({5, 0, 1.1}, {1, 0, 0}), 0.0, h));  // along the axis
}

TEST(CylinderX, OutsideSurfaceIsAPipe) {
  const CylinderX pipe{{-2.0, 1.5}, 0.1, 0.0, 50.0, false, -1e9, 0.6f};
  Hit h = Far();
  ASSERT_TRUE(pipe.Intersect(MakeRay({10, 0, 1.5}, {0, -1, 0}), 0.0, h));
  EXPECT_NEAR(h.t, 1.9, 1e-12);
  h = Far();
  ASSERT_TRUE(pipe.Intersect(MakeRay({10, 0, 1.5}, {0, -2, 0.1}), 0.0, h));  // grazes the top
  const Eigen::Vector3d p = Eigen::Vector3d(10, 0, 1.5) + h.t * Eigen::Vector3d(0, -2, 0.1).normalized();
  EXPECT_NEAR(std::hypot(p.y() + 2.0, p.z() - 1.5), 0.1, 1e-12);
  h = Far();
  EXPECT_FALSE(pipe.Intersect(MakeRay({10, -2.0, 1.5}, {0, 1, 0}), 0.0, h));  // from inside
  h = Far();
  EXPECT_FALSE(pipe.Intersect(MakeRay({10, 0, 1.5}, {0, 1, 0}), 0.0, h));  // away from it
}

// The grid must return what testing every primitive would, and a closed scene hides nothing.
void ExpectGridMatchesBruteForce(SceneKind kind, Eigen::Vector3d origin, bool closed) {
  const World world = BuildWorld(kind, 0.0, 100.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> el(-0.45, 0.45), az(-kPi, kPi);
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const double e = el(rng), a = az(rng);
    const Ray ray = MakeRay(origin, {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)});
    Hit brute = Far();
    brute.t = 500.0;
    bool any = false;
    for (const Primitive& p : world.scene.primitives()) {
      any |= std::visit([&](const auto& s) { return s.Intersect(ray, 1e-6, brute); }, p);
    }
    if (world.scene.ground()) any |= world.scene.ground()->Intersect(ray, 1e-6, brute);
    const std::optional<Hit> fast = world.scene.Cast(ray, 1e-6, 500.0);
    ASSERT_EQ(fast.has_value(), any) << SceneName(kind) << " ray " << i;
    if (any) {
      ++hits;
      ASSERT_NEAR(fast->t, brute.t, 1e-9) << SceneName(kind) << " ray " << i;
    }
  }
  if (closed) {
    EXPECT_EQ(hits, 4000) << SceneName(kind);
  } else {
    EXPECT_GT(hits, 2000) << SceneName(kind);
  }
}

TEST(NewScenes, GridMatchesBruteForce) {
  ExpectGridMatchesBruteForce(SceneKind::Tunnel, {30, 0.4, 0.6}, true);
  ExpectGridMatchesBruteForce(SceneKind::LongCorridor, {40, -0.5, 1.4}, true);
  ExpectGridMatchesBruteForce(SceneKind::StraightCorridor, {20, -0.2, 0.8}, true);
  ExpectGridMatchesBruteForce(SceneKind::EndlessCorridor, {200, -0.5, 1.4}, true);
  ExpectGridMatchesBruteForce(SceneKind::Campus, {40, 0.5, 1.6}, false);
}

TEST(NewScenes, TunnelPointsLieOnTheTunnel) {
  SimOptions options;
  options.num_scans = 30;
  options.noise_sigma = 0.0;
  options.motion = MotionKind::Legged;
  SensorSpec sensor = Vlp16();
  sensor.columns = 600;
  const Simulator sim(SceneKind::Tunnel, sensor, options);
  const Scan scan = sim.SimulateScan(25);
  ASSERT_GT(scan.size(), 8000u);
  int on_shell = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d p = sim.PoseAt(scan.t_start + scan.times[i]) * scan.points[i];
    const double r = std::hypot(p.y(), p.z() - 1.1);
    ASSERT_LT(r, 2.6 + 1e-6) << i;  // nothing outside the tunnel
    ASSERT_GT(p.z(), -1e-6) << i;   // nor below its floor
    on_shell += std::abs(r - 2.6) < 1e-6 ? 1 : 0;
  }
  EXPECT_GT(on_shell, static_cast<int>(scan.size()) / 3);
}

TEST(NewScenes, RealisticRangeModelFadesGrazingWalls) {
  // Along a 2.4 m corridor a grazing wall fades after ~20 m; the ideal model sees it to 60 m.
  SimOptions options;
  options.num_scans = 800;
  options.noise_sigma = 0.0;
  const Simulator ideal(SceneKind::StraightCorridor, Vlp16(), options);
  options.full_range_reflectivity = kRealisticFullRangeReflectivity;
  const Simulator real(SceneKind::StraightCorridor, Vlp16(), options);
  auto farthest_side_wall = [](const Simulator& sim, const Scan& scan) {
    double far = 0.0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const Eigen::Vector3d p = sim.PoseAt(scan.t_start + scan.times[i]) * scan.points[i];
      if (std::abs(std::abs(p.y()) - 1.2) < 1e-6) far = std::max(far, scan.points[i].norm());
    }
    return far;
  };
  const Scan a = ideal.SimulateScan(0), b = real.SimulateScan(0);
  EXPECT_LT(b.size(), a.size());
  EXPECT_GT(farthest_side_wall(ideal, a), 40.0);
  EXPECT_LT(farthest_side_wall(real, b), 30.0);
  EXPECT_GT(farthest_side_wall(real, b), 10.0);
}

// --- Presets ------------------------------------------------------------------------------

TEST(Presets, NamesAndDefaults) {
  const std::vector<std::string> expected = {"handheld-corridor",        "wheeled-corridor",
                                             "legged-tunnel",            "handheld-endless",
                                             "handheld-campus",          "wheeled-zigzag",
                                             "handheld-corridor-people", "wheeled-zigzag-people",
                                             "campus-crowd",             "follow-me",
                                             "handheld-look-around",     "handheld-aggressive",
                                             "wheeled-endless",          "campus-long-handheld",
                                             "campus-long-vehicle",      "two-floor",
                                             "warehouse-aisles"};
  EXPECT_EQ(PresetNames(), expected);
  for (const std::string& name : expected) {
    const auto p = FindPreset(name);
    ASSERT_TRUE(p.has_value()) << name;
    EXPECT_NE(p->motion, MotionKind::Constant) << name;
    EXPECT_DOUBLE_EQ(p->noise_sigma, 0.015) << name;
    const SimOptions o = p->Options(4);
    EXPECT_EQ(o.seed, 4u);
    EXPECT_EQ(o.num_scans, p->scans);
    EXPECT_EQ(o.motion, p->motion);
  }
  EXPECT_FALSE(FindPreset("nope").has_value());
}

struct Sampled {
  std::vector<Eigen::Vector3d> positions;  // at every scan start
  std::vector<double> speeds;              // scan to scan
};
Sampled SamplePreset(const Simulator& sim, int scans) {
  Sampled out;
  for (int i = 0; i < scans; ++i) out.positions.push_back(sim.PoseAt(sim.ScanStartTime(i)).translation());
  for (int i = 1; i < scans; ++i) {
    out.speeds.push_back((out.positions[i] - out.positions[i - 1]).norm() / sim.sensor().scan_period);
  }
  return out;
}

TEST(Presets, HandheldCorridorGoesOutTurnsAndComesBack) {
  const Preset preset = *FindPreset("handheld-corridor");
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Simulator sim(preset, Vlp16(), seed);
    EXPECT_EQ(sim.kind(), SceneKind::LongCorridor);
    EXPECT_EQ(sim.motion(), MotionKind::Handheld);
    const Sampled run = SamplePreset(sim, preset.scans);
    double x_max = -1e9;
    for (const Eigen::Vector3d& p : run.positions) {
      ASSERT_GT(p.x(), 0.5);  // inside the 130 x 2.4 x 2.8 m corridor
      ASSERT_LT(p.x(), 129.5);
      ASSERT_LT(std::abs(p.y()), 1.0);
      ASSERT_GT(p.z(), 1.0);
      ASSERT_LT(p.z(), 2.0);
      x_max = std::max(x_max, p.x());
    }
    EXPECT_LT(run.positions.front().x(), 10.0) << seed;
    EXPECT_GT(x_max, 90.0) << seed;              // out ~88 m ...
    EXPECT_LT(run.positions.back().x(), 10.0) << seed;  // ... and back near the start
    EXPECT_GT(StdDev(run.speeds), 0.1) << seed;
    // The walk fills the run: it ends standing, a few seconds before the last scan at most.
    EXPECT_LT(run.speeds.back(), 0.05) << seed;
    EXPECT_GT(run.speeds[run.speeds.size() - 60], 0.3) << seed;
  }
}

// The operator of handheld-look-around swings the sensor sideways and back: the heading leaves
// the path's by 45-100 deg at up to 120 deg/s about six times a minute, so that every 5th scan
// (2 Hz) can be tens of degrees from the last; without the swings the walk turns slowly.
TEST(Presets, LookAroundSwingsTheSensorFastAndFar) {
  auto yaw_steps = [](const Preset& preset, int every) {
    const Simulator sim(preset, Vlp16(), 1);
    std::vector<double> steps;
    for (int i = every; i < preset.scans; i += every) {
      const Eigen::Isometry3d a = sim.PoseAt(sim.ScanStartTime(i - every));
      const Eigen::Isometry3d b = sim.PoseAt(sim.ScanStartTime(i));
      steps.push_back(Eigen::AngleAxisd((a.inverse() * b).rotation()).angle() * 180.0 / M_PI);
    }
    std::sort(steps.begin(), steps.end());
    return steps;
  };
  const std::vector<double> look = yaw_steps(*FindPreset("handheld-look-around"), 5);
  Preset calm = *FindPreset("handheld-look-around");
  calm.look_arounds_per_minute = 0.0;
  const std::vector<double> walk = yaw_steps(calm, 5);
  std::printf("2 Hz steps, deg: look-around median %.1f p90 %.1f max %.1f; calm max %.1f\n",
              look[look.size() / 2], look[look.size() * 9 / 10], look.back(), walk.back());
  EXPECT_GT(look.back(), 40.0);   // a swing's fastest half second: up to 60 deg
  EXPECT_LT(look.back(), 61.0);
  EXPECT_GT(look[look.size() * 9 / 10], 10.0);
  EXPECT_LT(walk.back(), 0.5 * look.back());
}

TEST(Presets, EveryPresetStaysInsideItsSceneAndEndsWhereItShould) {
  for (const Preset& preset : Presets()) {
    const Simulator sim(preset, Vlp16(), 1);
    const Sampled run = SamplePreset(sim, preset.scans);
    // Distance along the scene's path (the sway and bobbing of the body not counted).
    const double path = sim.trajectory().carrier()->Eval(preset.scans * sim.sensor().scan_period).s;
    const Eigen::Vector3d first = run.positions.front(), last = run.positions.back();
    for (const Eigen::Vector3d& p : run.positions) ASSERT_TRUE(p.allFinite()) << preset.name;
    switch (preset.scene) {
      case SceneKind::Tunnel:
        for (const Eigen::Vector3d& p : run.positions) ASSERT_LT(std::hypot(p.y(), p.z() - 1.1), 2.0);
        EXPECT_NEAR(last.x() - first.x(), 110.0, 0.5) << preset.name;
        break;
      case SceneKind::StraightCorridor:
        EXPECT_NEAR(last.x() - first.x(), 56.0, 0.5) << preset.name;
        break;
      case SceneKind::EndlessCorridor:
        for (const Eigen::Vector3d& p : run.positions) {
          ASSERT_GT(p.x(), 125.0);  // the end walls (x = 0 and 460) stay > 120 m away
          ASSERT_LT(p.x(), 335.0);
        }
        EXPECT_NEAR(path, 401.57, 0.05) << preset.name;
        EXPECT_LT((last - first).norm(), 1.5) << preset.name;
        break;
      case SceneKind::Campus:
        EXPECT_NEAR(path, 300.27, 0.05) << preset.name;
        EXPECT_LT((last - first).head<2>().norm(), 1.0) << preset.name;
        break;
      case SceneKind::Zigzag:
        EXPECT_GT(last.x() - first.x(), 40.0) << preset.name;
        break;
      default:
        break;
    }
    if (preset.scene != SceneKind::Zigzag) {  // sized for the fastest drive: it may not arrive
      EXPECT_LT(run.speeds.back(), 0.05) << preset.name << ": should end standing";
    }
  }
}

}  // namespace
}  // namespace dammloam::sim
