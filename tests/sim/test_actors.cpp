// Moving actors: what the sensor sees of them, their labels, and the presets that carry them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "tools/benchmark/ghost_count.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr std::uint8_t kStatic = 0, kMoving = 1, kResting = 2;

SensorSpec SmallOs1() {
  SensorSpec s = Os1_64();
  s.columns = 512;
  return s;
}

// A sensor that stays where its scene starts (it creeps at a nanometre per second), without
// noise, so every point lies exactly on what it hit.
Simulator StillSensor(SceneKind scene, const SensorSpec& sensor = SmallOs1()) {
  SimOptions o;
  o.noise_sigma = 0.0;
  o.speed = 1e-9;
  o.num_scans = 100;
  return Simulator(scene, sensor, o);
}

Eigen::Vector3d ToWorld(const Simulator& sim, const Scan& scan, std::size_t i) {
  return sim.PoseAt(scan.t_start + scan.times[i]) * scan.points[i];
}

double DriveTime(const Simulator& sim, const Scan& scan, std::size_t i) {
  return scan.t_start + scan.times[i] - sim.options().t0;
}

// Where p lies relative to a box's faces: <= 0 inside, 0 on the surface.
double OutsideBy(const Box& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d local = box.rotation.transpose() * (p - box.center);
  return (local.cwiseAbs() - box.half_size).maxCoeff();
}

double PointToBox(const Eigen::Vector3d& p, const Box& box) {
  const Eigen::Vector3d local = box.rotation.transpose() * (p - box.center);
  return (local.cwiseAbs() - box.half_size).cwiseMax(0.0).norm();
}

struct Labelled {
  Scan scan;
  std::vector<std::uint8_t> labels;
};

Labelled Simulate(const Simulator& sim, int index) {
  Labelled out;
  out.scan = sim.SimulateScan(index, &out.labels);
  return out;
}

std::size_t CountLabel(const std::vector<std::uint8_t>& labels, std::uint8_t label) {
  return static_cast<std::size_t>(std::count(labels.begin(), labels.end(), label));
}

// Walks from x = 7 towards a sensor at the origin, stands 4 s at x = 5, walks on to x = 3.
TEST(Actors, PedestrianInFrontOfAStillSensorIsHitAndLabelledByItsMotion) {
  Simulator sim = StillSensor(SceneKind::Corridor);
  const ActorConfig ranges;
  std::mt19937 rng(5);
  const double height = std::uniform_real_distribution<double>(ranges.height_min, ranges.height_max)(rng);
  const Route walk({{7.0, 0.3}, {3.0, 0.3}}, 1.2, 0.0, {Stop{2.0, 4.0}});
  sim.SetActors(ActorSet({MakePedestrian(walk, height, 0.5f)}, std::nullopt));
  // Scan 10 (t = 1 s) walking, scan 40 standing since t = 1.67 s, scan 65 walking again.
  for (const auto& [index, expected] : {std::pair{10, kMoving}, std::pair{40, kResting}, std::pair{65, kMoving}}) {
    const Labelled run = Simulate(sim, index);
    ASSERT_EQ(run.labels.size(), run.scan.size());
    double top = 0.0;
    std::size_t on_actor = 0;
    for (std::size_t i = 0; i < run.scan.size(); ++i) {
      const Eigen::Vector3d p = ToWorld(sim, run.scan, i);
      const auto body = sim.actors().FootprintAt(0, DriveTime(sim, run.scan, i));
      ASSERT_TRUE(body.has_value());
      if (run.labels[i] == kStatic) {
        EXPECT_GT(OutsideBy(body->box, p), -1e-6) << "a static point inside the pedestrian, scan " << index;
        continue;
      }
      ++on_actor;
      EXPECT_EQ(run.labels[i], expected) << "scan " << index;
      EXPECT_LT(std::abs(OutsideBy(body->box, p)), 0.25) << "scan " << index;  // the head is narrower
      top = std::max(top, p.z());
    }
    EXPECT_GT(on_actor, 80u) << "scan " << index;  // 0.45 m wide at 3-6 m: 5-9 columns
    // The beams 0.7 deg apart reach the top of the head within a few centimetres.
    EXPECT_LE(top, height + 1e-6) << "scan " << index;
    EXPECT_GT(top, height - 0.08) << "scan " << index;
    EXPECT_GE(top, ranges.height_min - 0.08);
    EXPECT_LE(top, ranges.height_max);
  }
}

// Parked beside a still sensor 1.8 m up, so the roof is seen whole.
TEST(Actors, VehicleExtentFromItsPointsIsItsSize) {
  Simulator sim = StillSensor(SceneKind::Outdoor);
  const double yaw = 0.35;
  sim.SetActors(ActorSet({MakeVehicle(Route(Eigen::Vector2d(1.5, 6.0), yaw), 0.6f)}, sim.scene().ground()));
  const Labelled run = Simulate(sim, 3);
  const Box car = sim.actors().FootprintAt(0, 0.3)->box;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  std::size_t hits = 0;
  for (std::size_t i = 0; i < run.scan.size(); ++i) {
    if (run.labels[i] == kStatic) continue;
    EXPECT_EQ(run.labels[i], kResting);
    const Eigen::Vector3d local = car.rotation.transpose() * (ToWorld(sim, run.scan, i) - car.center);
    lo = lo.cwiseMin(local);
    hi = hi.cwiseMax(local);
    ++hits;
  }
  ASSERT_GT(hits, 500u);
  EXPECT_NEAR(hi.x() - lo.x(), 4.5, 0.15);
  EXPECT_NEAR(hi.y() - lo.y(), 1.8, 0.1);
  EXPECT_NEAR(hi.z() + car.half_size.z(), 1.5, 0.05);  // roof height above the ground under it
}

// A car driving away at 10 m/s: each point of its rear face was hit where the face was at that
// point's own firing time, so within one scan they spread along the motion by v * dt.
TEST(Actors, PointsAreHitAtTheirColumnsFiringTime) {
  Simulator sim = StillSensor(SceneKind::Corridor);
  constexpr double kSpeed = 10.0;
  sim.SetActors(ActorSet({MakeVehicle(Route({{5.0, 0.0}, {60.0, 0.0}}, kSpeed, 0.0), 0.6f)}, std::nullopt));
  const Labelled run = Simulate(sim, 2);  // rear face 4.75-5.75 m ahead
  double spread_lo = 1e9, spread_hi = -1e9, moving_lo = 1e9, moving_hi = -1e9;
  std::size_t rear = 0;
  for (std::size_t i = 0; i < run.scan.size(); ++i) {
    if (run.labels[i] == kStatic) continue;
    EXPECT_EQ(run.labels[i], kMoving);
    const double t = DriveTime(sim, run.scan, i);
    const Eigen::Vector3d p = ToWorld(sim, run.scan, i);
    const Box body = sim.actors().FootprintAt(0, t)->box;
    EXPECT_LT(PointToBox(p, body), 1e-6);  // on the car where it was at that instant
    if (std::abs(p.x() - (body.center.x() - body.half_size.x())) > 1e-6) continue;  // not the rear
    ++rear;
    spread_lo = std::min(spread_lo, p.x());
    spread_hi = std::max(spread_hi, p.x());
    moving_lo = std::min(moving_lo, p.x() - kSpeed * t);
    moving_hi = std::max(moving_hi, p.x() - kSpeed * t);
  }
  ASSERT_GT(rear, 100u);
  EXPECT_GT(spread_hi - spread_lo, 0.03);  // the face moved during the sweep over it
  EXPECT_LT(moving_hi - moving_lo, 1e-6);  // and by exactly v * (firing time difference)
}

TEST(Actors, LabelsComeInPointOrderAndLeaveThePointsAsTheyAre) {
  const Simulator sim(*FindPreset("handheld-corridor-people"), Vlp16(), 3);
  const Scan plain = sim.SimulateScan(80);
  const Labelled run = Simulate(sim, 80);
  ASSERT_EQ(run.labels.size(), run.scan.size());
  ASSERT_EQ(plain.points, run.scan.points);
  for (const std::uint8_t label : run.labels) EXPECT_LE(label, kResting);
  // Where no actor is in the way, a beam returns exactly what it returns without actors.
  const Simulator empty(*FindPreset("handheld-corridor"), Vlp16(), 3);
  const Scan bare = empty.SimulateScan(80);
  std::map<std::pair<float, int>, Eigen::Vector3d> bare_by_beam;
  for (std::size_t i = 0; i < bare.size(); ++i) bare_by_beam[{bare.times[i], bare.rings[i]}] = bare.points[i];
  std::size_t same = 0;
  for (std::size_t i = 0; i < run.scan.size(); ++i) {
    if (run.labels[i] != kStatic) continue;
    const auto it = bare_by_beam.find({run.scan.times[i], run.scan.rings[i]});
    ASSERT_NE(it, bare_by_beam.end()) << "point " << i;
    ASSERT_EQ(it->second, run.scan.points[i]) << "point " << i;
    ++same;
  }
  EXPECT_GT(same, bare.size() / 2);
  EXPECT_GT(CountLabel(run.labels, kMoving) + CountLabel(run.labels, kResting), 0u);
}

// The preset run: enough people and cars, each kind of actor it promises.
TEST(Actors, CampusCrowdHasACrowdTrafficAndAParkingAndALeavingCar) {
  const Simulator sim(*FindPreset("campus-crowd"), Vlp16(), 1);
  const ActorSet& actors = sim.actors();
  EXPECT_GE(actors.Count(ActorKind::Pedestrian), 40u);
  EXPECT_GE(actors.Count(ActorKind::Vehicle), 6u);
  EXPECT_EQ(actors.Count(ActorRole::Parking), 1u);
  EXPECT_EQ(actors.Count(ActorRole::Leaving), 1u);
  EXPECT_GE(actors.Count(ActorRole::Companion), 3u);
  EXPECT_LE(actors.Count(ActorRole::Companion), 5u);
  EXPECT_EQ(actors.Count(ActorKind::Door), 0u);
}

std::size_t FindRole(const ActorSet& actors, ActorRole role) {
  for (std::size_t i = 0; i < actors.size(); ++i) {
    if (actors.actors()[i].role == role) return i;
  }
  ADD_FAILURE() << "no actor with role " << static_cast<int>(role);
  return 0;
}

// Centre of the points that fell on one actor in a scan (world frame), and how many there were.
std::pair<Eigen::Vector3d, std::size_t> PointsOn(const Simulator& sim, std::size_t actor, int index) {
  const Labelled run = Simulate(sim, index);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for (std::size_t i = 0; i < run.scan.size(); ++i) {
    if (run.labels[i] == kStatic) continue;
    const auto body = sim.actors().FootprintAt(actor, DriveTime(sim, run.scan, i));
    const Eigen::Vector3d p = ToWorld(sim, run.scan, i);
    if (!body || PointToBox(p, body->box) > 0.05) continue;
    sum += p;
    ++n;
  }
  return {n > 0 ? Eigen::Vector3d(sum / static_cast<double>(n)) : sum, n};
}

TEST(Actors, ParkedCarThatLeavesIsStillThenItsPointsMove) {
  const Simulator sim(*FindPreset("campus-crowd"), Vlp16(), 1);
  const std::size_t car = FindRole(sim.actors(), ActorRole::Leaving);
  const double leaves = std::get<Route>(sim.actors().actors()[car].motion).start_time();
  const int scan_leaving = static_cast<int>(std::ceil(leaves / 0.1));
  const auto [parked_a, n_a] = PointsOn(sim, car, scan_leaving - 20);
  const auto [parked_b, n_b] = PointsOn(sim, car, scan_leaving - 10);
  const auto [driving_a, n_c] = PointsOn(sim, car, scan_leaving + 10);
  const auto [driving_b, n_d] = PointsOn(sim, car, scan_leaving + 20);
  for (const std::size_t n : {n_a, n_b, n_c, n_d}) ASSERT_GT(n, 20u);
  EXPECT_LT((parked_b - parked_a).norm(), 0.3);  // only the viewpoint changed
  EXPECT_GT((driving_b - driving_a).norm(), 2.0);  // >= 3 m/s for a second
  EXPECT_FALSE(sim.actors().MovingAt(car, leaves - 0.5));
  EXPECT_TRUE(sim.actors().MovingAt(car, leaves + 0.5));
}

TEST(Actors, FollowMeWalksTwoMetresAheadForTheWholeWalk) {
  const Preset preset = *FindPreset("follow-me");
  const Simulator sim(preset, Vlp16(), 2);
  ASSERT_EQ(sim.actors().size(), 1u);
  ASSERT_EQ(sim.actors().actors()[0].role, ActorRole::Leader);
  std::size_t ahead = 0, samples = 0;
  for (double t = 0.0; t < preset.scans * 0.1; t += 0.25) {
    const Eigen::Isometry3d sensor = sim.trajectory().Pose(t);
    const Box body = sim.actors().FootprintAt(0, t)->box;
    const Eigen::Vector3d to = body.center - sensor.translation();
    ASSERT_GT(to.head<2>().norm(), 1.5) << "t " << t;
    ASSERT_LT(to.head<2>().norm(), 2.5) << "t " << t;
    ASSERT_GT(PointToBox(sensor.translation(), body), 0.5) << "t " << t;
    ++samples;
    ahead += (sensor.linear().transpose() * to).x() > 1.0 ? 1 : 0;  // in front, not beside
  }
  EXPECT_GE(ahead, samples * 95 / 100);  // the U-turn may put it beside the sensor for a moment
  // And the sensor sees the person: points 1.5-2.5 m in front of it.
  const Labelled run = Simulate(sim, 300);
  std::size_t in_front = 0;
  for (std::size_t i = 0; i < run.scan.size(); ++i) {
    const double range = run.scan.points[i].norm();
    if (run.labels[i] != kStatic && run.scan.points[i].x() > 0.0 && range > 1.4 && range < 2.6) ++in_front;
  }
  EXPECT_GT(in_front, 100u);
}

// Every actor of every preset stays clear of the sensor and where people or cars can be: on the
// corridor's floor, or outside the campus buildings.
TEST(Actors, PresetActorsKeepClearOfTheSensorAndInsideTheScene) {
  for (const Preset& preset : Presets()) {
    if (!preset.actors.any()) continue;
    const Simulator sim(preset, Vlp16(), 1);
    ASSERT_FALSE(sim.actors().empty()) << preset.name;
    std::vector<Box> buildings;
    for (const Primitive& p : sim.scene().primitives()) {
      const Box* b = std::get_if<Box>(&p);
      if (b && b->half_size.z() > 2.0) buildings.push_back(*b);
    }
    for (double t = 0.0; t < preset.scans * 0.1; t += 0.1) {
      const Eigen::Vector3d sensor = sim.trajectory().Pose(t).translation();
      for (const ActorFootprint& f : sim.actors().FootprintsAt(t)) {
        ASSERT_GE(PointToBox(sensor, f.box), 0.5) << preset.name << " actor " << f.actor << " t " << t;
        const Eigen::Vector2d c = f.box.center.head<2>();
        for (const Box& building : buildings) {
          ASSERT_GT(OutsideBy(building, Eigen::Vector3d(c.x(), c.y(), building.center.z())), 0.0)
              << preset.name << " actor " << f.actor << " in a building at t " << t;
        }
        // Doors stand in their recesses, just beyond the side walls.
        const double recess = sim.actors().actors()[f.actor].kind == ActorKind::Door ? 0.4 : 0.0;
        if (preset.scene == SceneKind::LongCorridor) {
          ASSERT_LT(std::abs(c.y()), 1.2 + recess) << preset.name << " actor " << f.actor << " t " << t;
          ASSERT_GT(c.x(), 0.0);
          ASSERT_LT(c.x(), 130.0);
        }
        if (preset.scene == SceneKind::Zigzag) {
          ASSERT_LT(std::abs(c.y()), 2.0 + recess) << preset.name << " actor " << f.actor << " t " << t;
        }
      }
    }
  }
}

TEST(Actors, CorridorPeopleWalkBothWaysPassCloseAndAGroupKeepsPace) {
  const Preset preset = *FindPreset("handheld-corridor-people");
  const Simulator sim(preset, Vlp16(), 1);
  const ActorSet& actors = sim.actors();
  EXPECT_GE(actors.Count(ActorRole::Walker), 8u);
  EXPECT_EQ(actors.Count(ActorKind::Door), 2u);
  int forward = 0, backward = 0, close = 0;
  for (std::size_t i = 0; i < actors.size(); ++i) {
    const Actor& a = actors.actors()[i];
    if (a.role == ActorRole::Walker) {
      const Route& route = std::get<Route>(a.motion);
      (route.points().back().x() > route.points().front().x() ? forward : backward) += 1;
      double nearest = 1e9;
      for (double t = std::max(0.0, route.start_time()); t < std::min(route.end_time(), 170.0); t += 0.05) {
        if (!a.PresentAt(t)) continue;
        nearest = std::min(nearest, (actors.FootprintAt(i, t)->box.center - sim.trajectory().Pose(t).translation())
                                        .head<2>().norm());
      }
      close += nearest <= 1.0 ? 1 : 0;
    }
    if (a.role == ActorRole::Companion) {
      const Companion& c = std::get<Companion>(a.motion);
      EXPECT_GE(c.leave_time - c.join_time, 10.0);
      EXPECT_LE(c.leave_time - c.join_time, 30.0);
      // Alongside: the gap to the sensor stays what it is while they walk together.
      const double t0 = c.join_time + 1.0, t1 = c.leave_time - 1.0;
      const double gap0 = (actors.FootprintAt(i, t0)->box.center - sim.trajectory().Pose(t0).translation()).head<2>().norm();
      const double gap1 = (actors.FootprintAt(i, t1)->box.center - sim.trajectory().Pose(t1).translation()).head<2>().norm();
      EXPECT_NEAR(gap0, gap1, 0.15);
      EXPECT_GT(sim.trajectory().PathDistance(t1) - sim.trajectory().PathDistance(t0), 5.0);
    }
  }
  EXPECT_GE(forward, 2);
  EXPECT_GE(backward, 2);
  EXPECT_GE(close, 3);
  EXPECT_GE(actors.Count(ActorRole::Companion), 3u);
}

TEST(Actors, DoorsSwingOpenThenRest) {
  const Simulator sim(*FindPreset("wheeled-zigzag-people"), Vlp16(), 1);
  const ActorSet& actors = sim.actors();
  ASSERT_EQ(actors.Count(ActorKind::Door), 3u);
  for (std::size_t i = 0; i < actors.size(); ++i) {
    if (actors.actors()[i].kind != ActorKind::Door) continue;
    const Swing& swing = std::get<Swing>(actors.actors()[i].motion);
    const double opens = swing.open_time;
    EXPECT_FALSE(actors.MovingAt(i, opens - 0.5));
    EXPECT_TRUE(actors.MovingAt(i, opens + 1.0));
    EXPECT_FALSE(actors.MovingAt(i, opens + swing.duration + 1.5));
    const Eigen::Matrix3d closed = actors.FootprintAt(i, opens)->box.rotation;
    const Eigen::Matrix3d open = actors.FootprintAt(i, opens + swing.duration)->box.rotation;
    EXPECT_NEAR(Eigen::AngleAxisd(closed.transpose() * open).angle(), kPi / 2, 1e-9);
    // Closed, it lies flat in its recess: its leaf runs along the corridor.
    EXPECT_NEAR(std::abs(closed(0, 0)), 1.0, 1e-9);
  }
}

TEST(Actors, SweptVolumeTellsWhereAnActorHasLeft) {
  Simulator sim = StillSensor(SceneKind::Corridor);
  sim.SetActors(ActorSet({MakePedestrian(Route({{8.0, 0.5}, {3.0, 0.5}}, 1.0, 0.0), 1.7, 0.5f)}, std::nullopt));
  const double t0 = sim.options().t0;
  const SweptVolume swept = sim.ActorSweptVolume(t0, t0 + 3.0);  // walked from x = 8 to x = 5
  EXPECT_TRUE(swept.Vacated({7.9, 0.5, 1.0}));
  EXPECT_TRUE(swept.Vacated({6.5, 0.6, 0.2}));
  EXPECT_TRUE(swept.Occupied({5.0, 0.5, 1.0}));
  EXPECT_FALSE(swept.Vacated({5.0, 0.5, 1.0}));  // still there
  EXPECT_FALSE(swept.Occupied({4.0, 0.5, 1.0}));  // not yet
  EXPECT_FALSE(swept.Occupied({7.0, -0.5, 1.0}));  // beside its way
  EXPECT_FALSE(swept.Occupied({7.0, 0.5, 1.9}));   // above its head
  const std::vector<ActorFootprint> now = sim.ActorFootprintsAt(t0 + 3.0);
  ASSERT_EQ(now.size(), 1u);
  EXPECT_NEAR(now[0].box.center.x(), 5.0, 1e-9);
  EXPECT_TRUE(now[0].moving);
}

TEST(Actors, GhostsAreMapPointsWhereAnActorWasAndHasLeftAboveTheGroundItWalkedOn) {
  Simulator sim = StillSensor(SceneKind::Corridor);
  sim.SetActors(ActorSet({MakePedestrian(Route({{8.0, 0.5}, {3.0, 0.5}}, 1.0, 0.0), 1.7, 0.5f)}, std::nullopt));
  const double t0 = sim.options().t0;
  // The floor it walked on counts without a clearance, not with one.
  EXPECT_TRUE(sim.ActorSweptVolume(t0, t0 + 3.0).Occupied({6.5, 0.5, 0.03}));
  const SweptVolume swept = sim.ActorSweptVolume(t0, t0 + 3.0, 0.05, 0.05, 0.15);
  EXPECT_FALSE(swept.Occupied({6.5, 0.5, 0.03}));
  EXPECT_TRUE(swept.Vacated({6.5, 0.5, 0.3}));
  EXPECT_TRUE(swept.OccupiedAtEnd({5.0, 0.5, 1.0}));
  const std::vector<Eigen::Vector3d> map = {{7.9, 0.5, 1.0},    // where it was: a ghost
                                            {5.0, 0.5, 1.0},    // where it is now
                                            {7.0, -0.5, 1.0},   // beside its way
                                            {6.5, 0.5, 0.03}};  // the floor under its way
  const std::vector<PointClass> labels = {PointClass::Wall, PointClass::Edge, PointClass::Wall, PointClass::Ground};
  const bench::GhostCount count = bench::CountGhosts(map, labels, swept);
  EXPECT_EQ(count.points, 4u);
  EXPECT_EQ(count.ghosts, 1u);
  EXPECT_EQ(count.on_actors, 1u);
  EXPECT_EQ(count.ghosts_by_class[Index(PointClass::Wall)], 1u);
  EXPECT_EQ(count.ghost_indices, std::vector<std::size_t>{0});
}

}  // namespace
}  // namespace dammloam::sim
