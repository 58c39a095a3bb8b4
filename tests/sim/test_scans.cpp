#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/simulate/simulator.hpp"

namespace dammloam::sim {
namespace {

constexpr double kPi = std::numbers::pi;
// Corridor geometry used by the `corridor` scene: walls y = +-1.2, floor z = 0, ceiling z = 2.8.
constexpr double kHalfWidth = 1.2, kHeight = 2.8;

SimOptions Options(double noise, std::uint64_t seed = 1) {
  SimOptions o;
  o.noise_sigma = noise;
  o.seed = seed;
  o.num_scans = 50;
  return o;
}

SensorSpec SmallOs1() {
  SensorSpec s = Os1_64();
  s.columns = 512;
  return s;
}

Eigen::Vector3d ToWorld(const Simulator& sim, const Scan& scan, std::size_t i) {
  return sim.PoseAt(scan.t_start + scan.times[i]) * scan.points[i];
}

double Median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(Simulator, CorridorPointsLieOnTheWallsWithoutNoise) {
  const Simulator sim(SceneKind::Corridor, SmallOs1(), Options(0.0));
  for (const int index : {0, 7, 23}) {
    const Scan scan = sim.SimulateScan(index);
    ASSERT_GT(scan.size(), 10000u);
    // The far end wall is the farthest thing along x; the near one stands at x = -10.
    double far_x = -1e9;
    for (std::size_t i = 0; i < scan.size(); ++i) far_x = std::max(far_x, ToWorld(sim, scan, i).x());
    double worst = 0.0;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const Eigen::Vector3d p = ToWorld(sim, scan, i);
      const double d = std::min({std::abs(p.y() - kHalfWidth), std::abs(p.y() + kHalfWidth),
                                 std::abs(p.z()), std::abs(p.z() - kHeight),
                                 std::abs(p.x() + 10.0), std::abs(p.x() - far_x)});
      worst = std::max(worst, d);
    }
    EXPECT_LT(worst, 1e-6) << "scan " << index;
  }
}

// Range along each beam to the nearest corridor plane, from the sensor pose at firing time.
double TrueCorridorRange(const Eigen::Isometry3d& T, const Eigen::Vector3d& dir_sensor) {
  const Eigen::Vector3d o = T.translation(), d = T.linear() * dir_sensor;
  double best = 1e9;
  for (const auto& [axis, value] : {std::pair{1, kHalfWidth}, std::pair{1, -kHalfWidth},
                                    std::pair{2, 0.0}, std::pair{2, kHeight}}) {
    if (std::abs(d[axis]) < 1e-12) continue;
    const double t = (value - o[axis]) / d[axis];
    if (t > 0) best = std::min(best, t);
  }
  return best;
}

TEST(Simulator, RangeNoiseHasTheRequestedSigma) {
  constexpr double kSigma = 0.02;
  const Simulator sim(SceneKind::Corridor, SmallOs1(), Options(kSigma, 42));
  const Scan scan = sim.SimulateScan(3);
  double sum = 0.0, sum_sq = 0.0;
  double n = 0.0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double range = scan.points[i].norm();
    if (range > 8.0) continue;  // the end walls (10 m and more away) are not in the plane set
    n += 1.0;
    const double e = range - TrueCorridorRange(sim.PoseAt(scan.t_start + scan.times[i]),
                                               scan.points[i] / range);
    sum += e;
    sum_sq += e * e;
  }
  ASSERT_GT(n, 10000.0);
  EXPECT_NEAR(std::sqrt(sum_sq / n), kSigma, 0.05 * kSigma);
  EXPECT_NEAR(sum / n, 0.0, 5.0 * kSigma / std::sqrt(n));
}

TEST(Simulator, SameSeedSameScanOtherSeedDiffers) {
  const Simulator a(SceneKind::Outdoor, SmallOs1(), Options(0.01, 9));
  const Simulator b(SceneKind::Outdoor, SmallOs1(), Options(0.01, 9));
  const Simulator c(SceneKind::Outdoor, SmallOs1(), Options(0.01, 10));
  const Scan sa = a.SimulateScan(5), sb = b.SimulateScan(5), sc = c.SimulateScan(5);
  ASSERT_EQ(sa.size(), sb.size());
  for (std::size_t i = 0; i < sa.size(); ++i) ASSERT_EQ(sa.points[i], sb.points[i]) << i;
  ASSERT_EQ(sa.size(), sc.size());  // noise moves points, it does not remove them here
  std::size_t differ = 0;
  for (std::size_t i = 0; i < sa.size(); ++i) differ += sa.points[i] != sc.points[i] ? 1 : 0;
  EXPECT_GT(differ, sa.size() * 9 / 10);
}

TEST(Simulator, ThreadCountDoesNotChangeTheScan) {
  SimOptions serial = Options(0.01, 4);
  serial.threads = 1;
  const Simulator a(SceneKind::Zigzag, SmallOs1(), serial);
  const Simulator b(SceneKind::Zigzag, SmallOs1(), Options(0.01, 4));
  const Scan sa = a.SimulateScan(2), sb = b.SimulateScan(2);
  ASSERT_EQ(sa.size(), sb.size());
  for (std::size_t i = 0; i < sa.size(); ++i) {
    ASSERT_EQ(sa.points[i], sb.points[i]);
    ASSERT_EQ(sa.intensities[i], sb.intensities[i]);
  }
}

TEST(Simulator, RejectsARecessWithoutDepth) {
  for (const double depth : {0.0, -0.05, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    SimOptions options = Options(0.0);
    options.recess_depth = depth;
    EXPECT_THROW(Simulator(SceneKind::StraightCorridor, SmallOs1(), options), std::invalid_argument)
        << depth;
  }
}

// Where a point's azimuth lies within its range-image column, as a fraction in [0, 1): column
// c of N spans azimuths pi - 2 pi (c + 1) / N .. pi - 2 pi c / N, turning clockwise.
double PositionInColumn(const Eigen::Vector3d& p, int columns) {
  const double turns = (kPi - std::atan2(p.y(), p.x())) / (2.0 * kPi) * columns;
  return turns - std::floor(turns);
}

// Distance of a position in a column from the column's boundary, in columns (0 .. 0.5).
double FromBoundary(double position) { return std::min(position, 1.0 - position); }

TEST(Simulator, FiringPhaseMovesEveryFiringWithinItsColumn) {
  const SensorSpec sensor = SmallOs1();
  SimOptions midway = Options(0.0);
  midway.firing_phase = 0.5;
  const Scan locked = Simulator(SceneKind::Zigzag, sensor, Options(0.0)).SimulateScan(3);
  const Scan shifted = Simulator(SceneKind::Zigzag, sensor, midway).SimulateScan(3);
  ASSERT_GT(locked.size(), 10000u);
  ASSERT_GT(shifted.size(), 10000u);
  double worst_locked = 0.0, worst_shifted = 0.5;
  for (const Eigen::Vector3d& p : locked.points) {
    worst_locked = std::max(worst_locked, FromBoundary(PositionInColumn(p, sensor.columns)));
  }
  for (const Eigen::Vector3d& p : shifted.points) {
    worst_shifted = std::min(worst_shifted, FromBoundary(PositionInColumn(p, sensor.columns)));
  }
  EXPECT_LT(worst_locked, 1e-6);  // every firing on a boundary
  EXPECT_GT(worst_shifted, 0.5 - 1e-6);  // every firing midway between two
  for (const double bad : {1.0, -0.5, 2.0, std::numeric_limits<double>::quiet_NaN()}) {
    SimOptions options = Options(0.0);
    options.firing_phase = bad;
    EXPECT_THROW(Simulator(SceneKind::Zigzag, sensor, options), std::invalid_argument) << bad;
  }
}

TEST(Simulator, RandomFiringPhaseDiffersPerScanAndRepeatsPerSeed) {
  const SensorSpec sensor = SmallOs1();
  SimOptions random = Options(0.01);
  random.firing_phase = kRandomFiringPhase;
  const Simulator a(SceneKind::Zigzag, sensor, random), b(SceneKind::Zigzag, sensor, random);
  std::vector<double> phases;
  for (const int index : {0, 1, 2, 3, 4, 5}) {
    const Scan scan = a.SimulateScan(index);
    const Scan again = b.SimulateScan(index);
    ASSERT_EQ(scan.points, again.points);
    // One offset per scan: the first point's position holds for every point (noise is radial).
    const double phase = PositionInColumn(scan.points.front(), sensor.columns);
    for (const Eigen::Vector3d& p : scan.points) {
      const double d = std::abs(PositionInColumn(p, sensor.columns) - phase);
      ASSERT_LT(std::min(d, 1.0 - d), 1e-6);
    }
    phases.push_back(phase);
  }
  std::sort(phases.begin(), phases.end());
  EXPECT_GT(phases.back() - phases.front(), 0.3);  // six draws from [0, 1)
}

TEST(Simulator, DropoutRemovesTheRequestedShare) {
  SimOptions with = Options(0.0);
  with.dropout = 0.3;
  const Scan full = Simulator(SceneKind::Zigzag, SmallOs1(), Options(0.0)).SimulateScan(1);
  const Scan thinned = Simulator(SceneKind::Zigzag, SmallOs1(), with).SimulateScan(1);
  EXPECT_NEAR(static_cast<double>(thinned.size()) / full.size(), 0.7, 0.02);
}

TEST(Simulator, TimesRingsAndFiringOrderAreValid) {
  const Simulator sim(SceneKind::Outdoor, SmallOs1(), Options(0.0));
  const Scan scan = sim.SimulateScan(4);
  ASSERT_TRUE(scan.has_times());
  ASSERT_TRUE(scan.has_rings());
  ASSERT_EQ(scan.intensities.size(), scan.size());
  EXPECT_DOUBLE_EQ(scan.t_start, sim.options().t0 + 4 * 0.1);
  const SensorSpec& spec = sim.sensor();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    ASSERT_GE(scan.times[i], 0.0f);
    ASSERT_LT(scan.times[i], spec.scan_period);
    ASSERT_GE(scan.rings[i], 0);
    ASSERT_LT(scan.rings[i], spec.rings());
    ASSERT_GE(scan.intensities[i], 0.0f);
    const double r = scan.points[i].norm();
    ASSERT_GE(r, spec.min_range);
    ASSERT_LE(r, spec.max_range);
    if (i > 0) {
      // Column by column, all rings of a column in order.
      ASSERT_GE(scan.times[i], scan.times[i - 1]);
      if (scan.times[i] == scan.times[i - 1]) {
        ASSERT_GT(scan.rings[i], scan.rings[i - 1]);
      }
    }
    // Each point lies on its own beam: the ring's elevation and its column's azimuth.
    const Eigen::Vector3d& p = scan.points[i];
    const double el = std::atan2(p.z(), p.head<2>().norm()) * 180.0 / kPi;
    ASSERT_NEAR(el, spec.vertical_angles_deg[static_cast<std::size_t>(scan.rings[i])], 1e-9);
    const int column = static_cast<int>(std::lround(scan.times[i] / spec.scan_period * spec.columns));
    const double daz = std::remainder(std::atan2(p.y(), p.x()) - ColumnAzimuth(spec, column), 2 * kPi);
    ASSERT_NEAR(daz, 0.0, 1e-9);
  }
  // Most of an outdoor scene returns: every downward beam hits the ground.
  EXPECT_GT(scan.size(), static_cast<std::size_t>(spec.rings() * spec.columns / 2));
}

TEST(Simulator, Vlp16BeamsAreEveryTwoDegrees) {
  const SensorSpec vlp = Vlp16();
  ASSERT_EQ(vlp.rings(), 16);
  EXPECT_EQ(vlp.columns, 1800);
  for (int r = 0; r < 16; ++r) EXPECT_NEAR(vlp.vertical_angles_deg[static_cast<std::size_t>(r)], 15.0 - 2.0 * r, 1e-12);
  const Simulator sim(SceneKind::Zigzag, vlp, Options(0.0));
  const Scan scan = sim.SimulateScan(0);
  std::vector<int> per_ring(16, 0);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d& p = scan.points[i];
    const double el = std::atan2(p.z(), p.head<2>().norm()) * 180.0 / kPi;
    ASSERT_NEAR(el, 15.0 - 2.0 * scan.rings[i], 1e-9);
    ++per_ring[static_cast<std::size_t>(scan.rings[i])];
  }
  for (int r = 0; r < 16; ++r) EXPECT_GT(per_ring[static_cast<std::size_t>(r)], 1000) << "ring " << r;
  const SensorModel model = sim.sensor_model();
  EXPECT_EQ(model.rings, 16);
  EXPECT_DOUBLE_EQ(model.min_range, 0.4);
  EXPECT_DOUBLE_EQ(model.max_range, 100.0);
}

TEST(Simulator, The128BeamSensorsHaveTheirRingsAndColumns) {
  for (const std::string& name : SensorNames()) {
    const auto spec = MakeSensorSpec(name);
    ASSERT_TRUE(spec) << name;
    EXPECT_EQ(spec->name, name);
    EXPECT_EQ(Validate(*spec), "") << name;
  }
  const SensorSpec os1 = *MakeSensorSpec("os1-128x2048");
  ASSERT_EQ(os1.rings(), 128);
  EXPECT_EQ(os1.columns, 2048);
  EXPECT_NEAR(os1.vertical_angles_deg.front() - os1.vertical_angles_deg[1], 45.0 / 127, 1e-12);
  EXPECT_EQ(MakeSensorSpec("os1-128")->columns, 1024);

  const SensorSpec vls = Vls128();
  ASSERT_EQ(vls.rings(), 128);
  EXPECT_EQ(vls.columns, 1800);
  EXPECT_DOUBLE_EQ(vls.vertical_angles_deg.front(), 15.0);
  EXPECT_NEAR(vls.vertical_angles_deg.back(), -25.0, 1e-12);
  int fine = 0;  // gaps of 0.11 deg, all of them within a few degrees of the horizon
  for (std::size_t r = 1; r < vls.vertical_angles_deg.size(); ++r) {
    const double gap = vls.vertical_angles_deg[r - 1] - vls.vertical_angles_deg[r];
    EXPECT_GT(gap, 0.1);
    EXPECT_LT(gap, 0.5);
    if (gap < 0.12) {
      ++fine;
      EXPECT_LT(std::abs(vls.vertical_angles_deg[r]), 4.1);
    }
  }
  EXPECT_EQ(fine, 55);

  // A scan of each: one return per beam and column at most, every ring seen outdoors.
  for (const SensorSpec& spec : {os1, vls}) {
    const Simulator sim(SceneKind::Outdoor, spec, Options(0.0));
    const Scan scan = sim.SimulateScan(0);
    EXPECT_LE(scan.size(), static_cast<std::size_t>(spec.rings() * spec.columns));
    EXPECT_GT(scan.size(), static_cast<std::size_t>(spec.rings() * spec.columns / 2)) << spec.name;
    std::vector<int> per_ring(128, 0);
    for (std::size_t i = 0; i < scan.size(); ++i) ++per_ring[static_cast<std::size_t>(scan.rings[i])];
    for (int r = 64; r < 128; ++r) EXPECT_GT(per_ring[static_cast<std::size_t>(r)], 0) << spec.name << " ring " << r;
  }
}

TEST(Simulator, InvalidSensorIsRejectedWithAReason) {
  SensorSpec bad = Os1_64();
  bad.vertical_angles_deg[5] = 40.0;  // not decreasing
  try {
    const Simulator sim(SceneKind::Corridor, bad, {});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ring 5"), std::string::npos) << e.what();
  }
}

TEST(Simulator, OutdoorLoopReturnsToItsStart) {
  SimOptions o = Options(0.0);
  const Simulator sim(SceneKind::Outdoor, SmallOs1(), o);
  // One lap at cruise speed plus the half ramp-up lost while accelerating from rest.
  const double lap = (2 * 28 + 2 * 18 + 2 * kPi * 6) / DefaultSpeed(SceneKind::Outdoor) +
                     0.5 * sim.trajectory().spec().ramp_up;
  const Eigen::Vector3d start = sim.PoseAt(o.t0).translation();
  double farthest = 0.0;
  for (double t = 0; t < lap; t += 1.0) {
    farthest = std::max(farthest, (sim.PoseAt(o.t0 + t).translation() - start).norm());
  }
  EXPECT_GT(farthest, 30.0);
  EXPECT_LT((sim.PoseAt(o.t0 + lap).translation() - start).norm(), 0.3);
}

TEST(Simulator, CorridorReturnComesBackTheOtherWay) {
  SimOptions o = Options(0.0);
  o.num_scans = 300;  // 30 s: 14 m out, U-turn, back
  const Simulator sim(SceneKind::CorridorReturn, SmallOs1(), o);
  // 29.9 s of driving plus the half ramp-up lost while accelerating from rest.
  const double end_t = 29.9 + 0.5 * sim.trajectory().spec().ramp_up;
  const Eigen::Isometry3d start = sim.PoseAt(o.t0), end = sim.PoseAt(o.t0 + end_t);
  EXPECT_LT(std::abs(end.translation().x() - start.translation().x()), 1.0);
  EXPECT_LT(start.linear().col(0).dot(end.linear().col(0)), -0.95);  // facing the other way
}

// Ground truth must be smooth everywhere, including at the very first scan (t = t0).
TEST(Simulator, TrajectoryIsSmoothFromTheStart) {
  for (const std::string& name : SceneNames()) {
    const Simulator sim(*ParseSceneKind(name), SmallOs1(), Options(0.0));
    const double speed = DefaultSpeed(sim.kind());
    constexpr double kDt = 0.002;
    Eigen::Isometry3d prev = sim.PoseAt(sim.options().t0 - kDt);
    for (double t = 0.0; t < 0.3; t += kDt) {
      const Eigen::Isometry3d T = sim.PoseAt(sim.options().t0 + t);
      ASSERT_LT((T.translation() - prev.translation()).norm(), 2.0 * speed * kDt) << name << " t " << t;
      ASSERT_LT(Eigen::AngleAxisd(prev.linear().transpose() * T.linear()).angle(), 0.01) << name << " t " << t;
      prev = T;
    }
  }
}

// --- Motion distortion: deskewing with the ground truth must make neighbour scans agree. ---

struct Cloud {
  std::vector<Eigen::Vector3d> pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return pts[i][static_cast<int>(dim)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3>;

std::vector<Eigen::Vector3d> WorldPoints(const Simulator& sim, const Scan& scan, bool deskew) {
  std::vector<Eigen::Vector3d> out;
  const Eigen::Isometry3d T_start = sim.PoseAt(scan.t_start);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    out.push_back(deskew ? ToWorld(sim, scan, i) : T_start * scan.points[i]);
  }
  return out;
}

// Median distance of `query` points to the local plane of their 8 nearest neighbours in `ref`,
// over points on vertical surfaces only: ground is blind to horizontal displacement.
double MedianPointToFacade(const std::vector<Eigen::Vector3d>& query, const Cloud& ref,
                           const KdTree& tree) {
  std::vector<double> d;
  constexpr std::size_t kK = 8;
  for (std::size_t i = 0; i < query.size(); i += 3) {
    std::array<unsigned int, kK> idx{};  // nanoflann's default index type
    std::array<double, kK> sq{};
    if (tree.knnSearch(query[i].data(), kK, idx.data(), sq.data()) < kK || sq.back() > 0.5 * 0.5) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const unsigned int j : idx) mean += ref.pts[j];
    mean /= kK;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const unsigned int j : idx) cov += (ref.pts[j] - mean) * (ref.pts[j] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Eigen::Vector3d normal = eig.eigenvectors().col(0);
    if (std::abs(normal.z()) > 0.3) continue;
    d.push_back(std::abs(normal.dot(query[i] - mean)));
  }
  EXPECT_GT(d.size(), 2000u);
  return Median(d);
}

// Against the correctly deskewed neighbour scan (the true geometry), a scan deskewed with the
// ground truth agrees within the noise while the same scan taken as rigid (every point at the
// scan-start pose) is off by the distance driven during the sweep.
TEST(Simulator, GroundTruthDeskewAlignsNeighbourScansAndRawScansDoNot) {
  constexpr double kSigma = 0.01;
  SimOptions o = Options(kSigma);
  o.speed = 3.0;  // 0.3 m and, in a corner of the loop, 3 deg of turn within one scan
  const Simulator sim(SceneKind::Outdoor, Os1_64(), o);
  const Scan a = sim.SimulateScan(110), b = sim.SimulateScan(111);  // in the first corner
  Cloud ref{WorldPoints(sim, b, true)};
  KdTree tree(3, ref, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const double deskewed = MedianPointToFacade(WorldPoints(sim, a, true), ref, tree);
  const double raw = MedianPointToFacade(WorldPoints(sim, a, false), ref, tree);
  RecordProperty("median_deskewed_m", std::to_string(deskewed));
  RecordProperty("median_raw_m", std::to_string(raw));
  EXPECT_LT(deskewed, 1.5 * kSigma) << "deskewed " << deskewed;
  EXPECT_GT(raw, 3.0 * deskewed) << "raw " << raw << " deskewed " << deskewed;
}

}  // namespace
}  // namespace dammloam::sim
