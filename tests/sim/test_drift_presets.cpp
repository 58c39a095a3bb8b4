// The drift and loop-closure presets (issue 53) have what they are for, checked on the ground
// truth and a few thousand rays only (no scans simulated): a long route with revisits, some in
// the opposite direction; two floors 3 m apart with a climbed staircase; identical aisles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "tools/simulate/drift_scenes.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

struct Sample {
  double t = 0.0;  // seconds since the start
  Eigen::Vector3d position;
  double direction = 0.0;  // of travel (rad), from the positions 1 s apart
  double speed = 0.0;      // m/s over that second
  double distance = 0.0;   // travelled since the start, metres
};

// The ground truth every `step` seconds of the preset's whole run.
std::vector<Sample> SampleRun(const Simulator& sim, int scans, double step) {
  std::vector<Sample> out;
  const double duration = scans * sim.sensor().scan_period;
  for (double t = 0.0; t < duration; t += step) {
    const Eigen::Vector3d a = sim.trajectory().Pose(t).translation();
    const Eigen::Vector3d b = sim.trajectory().Pose(t + 1.0).translation();
    const double distance = out.empty() ? 0.0 : out.back().distance + (a - out.back().position).norm();
    out.push_back({t, a, std::atan2(b.y() - a.y(), b.x() - a.x()), (b - a).head<2>().norm(), distance});
  }
  return out;
}

double AngleBetween(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * std::numbers::pi)); }

// A stretch of the run that passes within `radius` of where it was more than `min_gap` metres
// of travel before; `opposite`: somewhere on it, travelling more than 135 deg from the
// direction it had there before.
struct Revisit {
  double t = 0.0;
  bool opposite = false;
};

// One revisit per stretch: a new one starts after `split` metres without a match.
std::vector<Revisit> Revisits(const std::vector<Sample>& run, double radius, double min_gap, double split,
                              double max_height_difference = 1e9) {
  std::vector<Revisit> out;
  double last_match = -1e9;
  for (const Sample& now : run) {
    for (const Sample& before : run) {
      if (before.distance > now.distance - min_gap) break;
      if ((now.position - before.position).head<2>().norm() > radius) continue;
      if (std::abs(now.position.z() - before.position.z()) > max_height_difference) continue;
      if (now.distance - last_match > split) out.push_back({now.t, false});
      out.back().opposite |= now.speed > 0.2 && AngleBetween(now.direction, before.direction) > 135.0 / kRadToDeg;
      last_match = now.distance;
      break;
    }
  }
  return out;
}

int CountOpposite(const std::vector<Revisit>& revisits) {
  return static_cast<int>(std::count_if(revisits.begin(), revisits.end(), [](const Revisit& r) { return r.opposite; }));
}

// The path itself every `step` metres (no carrier: cheap for the 20-minute walk).
std::vector<Sample> SamplePath(const Path& path, double step) {
  std::vector<Sample> out;
  for (double s = 0.0; s <= path.length(); s += step) {
    const Path::State state = path.At(s);
    out.push_back({s, Eigen::Vector3d(state.position.x(), state.position.y(), 0.0), state.heading, 1.0, s});
  }
  return out;
}

void ExpectLongRouteWithRevisits(const std::string& name, const std::vector<Sample>& run) {
  const std::vector<Revisit> revisits = Revisits(run, 4.0, 150.0, 30.0);
  std::printf("%s: %.0f m, %zu revisits, %d in the opposite direction\n", name.c_str(), run.back().distance,
              revisits.size(), CountOpposite(revisits));
  EXPECT_GE(run.back().distance, 1500.0) << name;
  EXPECT_GE(revisits.size(), 4u) << name;
  EXPECT_GE(CountOpposite(revisits), 2) << name;
}

TEST(DriftPresets, CampusLongRouteIsLongAndRevisitsStreetsBothWays) {
  // The walk's route, built as the preset builds it (corners sized by the walker's top speed);
  // that the walk reaches its end within the run is checked for every preset in test_motion.
  const World walk = BuildWorld(SceneKind::CampusLong, ToParams(HandheldProfile{}).speed_max, 1200.0);
  ExpectLongRouteWithRevisits("campus-long-handheld route", SamplePath(walk.motion.path, 1.0));
  // The drive, from its ground truth.
  const Preset preset = *FindPreset("campus-long-vehicle");
  const Simulator sim(preset, Vlp16(), 1);
  EXPECT_EQ(sim.kind(), SceneKind::CampusLong);
  const std::vector<Sample> run = SampleRun(sim, preset.scans, 0.5);
  ExpectLongRouteWithRevisits(preset.name, run);
  EXPECT_LT(run.back().speed, 0.05) << "ends standing";
}

// The car keeps to 5-10 m/s between corners and stops, its sensor 1.8 m above the road, and
// its body pitches and rolls a little on the suspension beyond what the ground slope gives.
TEST(DriftPresets, VehicleDrivesAtCarSpeedsWithTheSensorOnTheRoof) {
  const Preset preset = *FindPreset("campus-long-vehicle");
  EXPECT_EQ(preset.motion, MotionKind::Vehicle);
  const Simulator sim(preset, Vlp16(), 2);
  const Trajectory& trajectory = sim.trajectory();
  const Heightfield& ground = *trajectory.spec().ground;
  std::vector<double> speeds;
  double fastest = 0.0, largest_lateral = 0.0;
  // Over half a second, so the few millimetres of vibration do not look like acceleration.
  constexpr double kStep = 0.5;
  for (double t = 0.0; t + 2.0 * kStep < preset.scans * 0.1; t += 0.1) {
    const Eigen::Vector3d a = trajectory.Pose(t).translation(), b = trajectory.Pose(t + kStep).translation(),
                          c = trajectory.Pose(t + 2.0 * kStep).translation();
    const double v = (b - a).head<2>().norm() / kStep;
    fastest = std::max(fastest, v);
    if (v > 1.0) speeds.push_back(v);
    const Eigen::Vector2d accel = (c - 2.0 * b + a).head<2>() / (kStep * kStep);
    const Eigen::Vector2d along = (c - a).head<2>().normalized();
    largest_lateral = std::max(largest_lateral, std::abs(along.x() * accel.y() - along.y() * accel.x()));
    EXPECT_NEAR(a.z() - ground.Height(a.x(), a.y()), 1.8, 0.05) << t;
  }
  std::nth_element(speeds.begin(), speeds.begin() + static_cast<long>(speeds.size() / 2), speeds.end());
  const double median = speeds[speeds.size() / 2];
  std::printf("vehicle: median %.1f m/s, fastest %.1f m/s, largest lateral acceleration %.2f m/s^2\n",
              median, fastest, largest_lateral);
  EXPECT_GT(median, 5.0);
  EXPECT_LT(fastest, 10.5);
  EXPECT_LT(largest_lateral, 2.5);  // corners at ~1.5 m/s^2, vibration on top
  ASSERT_NE(trajectory.carrier(), nullptr);
  double largest_suspension_deg = 0.0;
  for (double t = 0.0; t < preset.scans * 0.1; t += 0.5) {
    const CarrierMotion::Body body = trajectory.carrier()->BodyAt(t, 0.0);  // no vibration
    largest_suspension_deg = std::max({largest_suspension_deg, std::abs(body.pitch) * kRadToDeg,
                                       std::abs(body.roll) * kRadToDeg});
  }
  EXPECT_GT(largest_suspension_deg, 0.3);
  EXPECT_LT(largest_suspension_deg, 2.0);
}

// Every column fires at its own time: the car's pose must be continuous through a corner, where
// the suspension rolls it (no jump between 1 ms samples beyond its speed, vibration and turn).
TEST(DriftPresets, VehiclePoseIsContinuousThroughACorner) {
  MotionSpec spec;
  spec.path = Path().Line(150.0).Arc(10.0, std::numbers::pi / 2).Line(150.0);
  spec.kind = MotionKind::Vehicle;
  spec.seed = 3;
  spec.duration = 70.0;
  const Trajectory drive(spec);
  constexpr double kDt = 0.001;
  Eigen::Isometry3d before = drive.Pose(-kDt), now = drive.Pose(0.0);
  double worst_step = 0.0, worst_second = 0.0, worst_turn = 0.0;
  for (double t = kDt; t < 70.0; t += kDt) {
    const Eigen::Isometry3d next = drive.Pose(t);
    worst_step = std::max(worst_step, (next.translation() - now.translation()).norm());
    worst_second = std::max(worst_second, (next.translation() - 2.0 * now.translation() + before.translation()).norm());
    worst_turn = std::max(worst_turn, Eigen::AngleAxisd((now.inverse() * next).rotation()).angle());
    before = now;
    now = next;
  }
  EXPECT_LT(worst_step, 10.5 * kDt);
  EXPECT_LT(worst_second, 200.0 * kDt * kDt);
  EXPECT_LT(worst_turn, 1.0 * kDt);  // rad: the corner's 0.4 rad/s and the vibration's rate
}

TEST(DriftPresets, TwoFloorClimbsTheStairsAndWalksTheSameCorridorsRightAbove) {
  const Preset preset = *FindPreset("two-floor");
  const Simulator sim(preset, Vlp16(), 1);
  const std::vector<Sample> run = SampleRun(sim, preset.scans, 0.5);
  const double floor1 = run.front().position.z();
  EXPECT_NEAR(floor1, 1.4, 0.05);
  EXPECT_NEAR(run.back().position.z() - floor1, kTwoFloorStorey, 0.05);
  // The climb: from floor 1 to floor 2 once, within half a minute, never going down on the way.
  std::vector<const Sample*> climbing;
  for (const Sample& s : run) {
    if (s.position.z() > floor1 + 0.2 && s.position.z() < floor1 + kTwoFloorStorey - 0.2) climbing.push_back(&s);
  }
  ASSERT_GE(climbing.size(), 4u);
  EXPECT_LT(climbing.back()->t - climbing.front()->t, 30.0);
  for (std::size_t i = 1; i < climbing.size(); ++i) {
    EXPECT_GT(climbing[i]->position.z(), climbing[i - 1]->position.z() - 0.05);
    EXPECT_NEAR(climbing[i]->t - climbing[i - 1]->t, 0.5, 1e-9);  // one stretch, no second climb
  }
  // Floor 2's walk lies right above floor 1's: most of it within 0.5 m of a floor-1 place.
  std::vector<Eigen::Vector3d> lower, upper;
  for (const Sample& s : run) {
    if (s.position.z() < floor1 + 0.1) lower.push_back(s.position);
    if (s.position.z() > floor1 + kTwoFloorStorey - 0.1) upper.push_back(s.position);
  }
  int above = 0;
  for (const Eigen::Vector3d& p : upper) {
    const bool over = std::any_of(lower.begin(), lower.end(), [&](const Eigen::Vector3d& q) {
      return (p - q).head<2>().norm() < 0.5;
    });
    above += over ? 1 : 0;
  }
  EXPECT_GT(above, static_cast<int>(0.85 * static_cast<double>(upper.size())));
  // True revisits: each floor passes its own start again (same height), a minute or more later.
  const std::vector<Revisit> same_floor = Revisits(run, 1.0, 60.0, 10.0, 0.3);
  int floor1_revisits = 0, floor2_revisits = 0;
  for (const Revisit& r : same_floor) {
    const double z = sim.trajectory().Pose(r.t).translation().z();
    (z < floor1 + 1.0 ? floor1_revisits : floor2_revisits) += 1;
  }
  EXPECT_GE(floor1_revisits, 1);
  EXPECT_GE(floor2_revisits, 1);
}

// Every aisle looks the same from its middle: a fan of beams from the centre of each aisle gives
// identical ranges up to 3.5 m and 2.58 m sideways (its two racks, short of their back uprights;
// beyond them one aisle sees the next rack's back, an outer aisle the hall's wall).
std::vector<double> RangesFrom(const Scene& scene, const Eigen::Vector3d& origin) {
  std::vector<double> ranges;
  for (int az = 0; az < 360; az += 2) {
    for (int el = -15; el <= 15; el += 2) {
      const double a = az / kRadToDeg, e = el / kRadToDeg;
      const Ray ray{origin, Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e))};
      const std::optional<Hit> hit = scene.Cast(ray, 1e-6, 3.5);
      ranges.push_back(hit && std::abs(hit->t * ray.dir.y()) < 2.58 ? hit->t : -1.0);
    }
  }
  return ranges;
}

TEST(DriftPresets, WarehouseAislesAreIdenticalAndDrivenBothWays) {
  const Preset preset = *FindPreset("warehouse-aisles");
  const Simulator sim(preset, Vlp16(), 1);
  const double mid_x = 0.5 * (kWarehouseRackX0 + kWarehouseRackX1) + 0.3;
  auto aisle_y = [](int k) { return kWarehouseAisleY0 + k * kWarehouseAislePitch; };
  const std::vector<double> first = RangesFrom(sim.scene(), {mid_x, aisle_y(0), 0.8});
  const long hits = std::count_if(first.begin(), first.end(), [](double r) { return r > 0.0; });
  EXPECT_GT(hits, static_cast<long>(first.size() / 3));  // the racks are there
  for (int k = 1; k < kWarehouseAisles; ++k) {
    const std::vector<double> other = RangesFrom(sim.scene(), {mid_x, aisle_y(k), 0.8});
    for (std::size_t i = 0; i < first.size(); ++i) ASSERT_NEAR(other[i], first[i], 1e-9) << "aisle " << k << " ray " << i;
  }
  // The robot drives every aisle once, then aisle 2 again against and aisle 0 again along its
  // first direction: passes are the separate stretches in an aisle's middle.
  const std::vector<Sample> run = SampleRun(sim, preset.scans, 0.5);
  for (int k = 0; k < kWarehouseAisles; ++k) {
    std::vector<double> passes;  // direction of each
    bool inside = false;
    for (const Sample& s : run) {
      const bool in_aisle = std::abs(s.position.y() - aisle_y(k)) < 0.3 && s.position.x() > kWarehouseRackX0 + 4.0 &&
                            s.position.x() < kWarehouseRackX1 - 4.0;
      if (in_aisle && !inside) passes.push_back(s.direction);
      inside = in_aisle;
    }
    ASSERT_EQ(passes.size(), k == 0 || k == 2 ? 2u : 1u) << "aisle " << k;
    if (k == 0) {
      EXPECT_LT(AngleBetween(passes[0], passes[1]), 10.0 / kRadToDeg);
    }
    if (k == 2) {
      EXPECT_GT(AngleBetween(passes[0], passes[1]), 170.0 / kRadToDeg);
    }
  }
  const std::vector<Revisit> revisits = Revisits(run, 1.0, 60.0, 10.0);
  ASSERT_FALSE(revisits.empty());
  EXPECT_GE(CountOpposite(revisits), 1);
}

}  // namespace
}  // namespace dammloam::sim
