#include "core/preprocess/classifier.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>

#include "tests/core/lidar_raycast.hpp"

namespace dammloam {
namespace {

using test::CastScan;
using test::Scene;
using test::SyntheticLidar;

constexpr double kDeg = std::numbers::pi / 180.0;

// 14 m x 12 m x 3 m room, floor at z = 0.
Scene BoxRoom() {
  Scene scene;
  scene.has_room = true;
  scene.room = {{-7.0, -6.0, 0.0}, {7.0, 6.0, 3.0}};
  return scene;
}

PointClass ExpectedClass(int surface) {
  if (surface == 4) return PointClass::Ground;
  if (surface == 5) return PointClass::Roof;
  return PointClass::Wall;
}

struct RoomLabels {
  Scan scan;
  std::vector<int> surfaces;
  std::vector<PointClass> labels;  // per point (the winner of every pixel; no collisions here)
  std::vector<Eigen::Vector3d> world;
  // Away from the face's edges: every pixel within 2 rows/columns (the reach of the 3x3 window
  // of central-difference normals) shows the same face.
  std::vector<bool> interior;
};

bool InteriorPixel(const RangeImage& image, const std::vector<int>& surfaces, int r, int c) {
  const int s = surfaces[static_cast<std::size_t>(image.index(r, c))];
  for (int dr = -2; dr <= 2; ++dr) {
    if (r + dr < 0 || r + dr >= image.rows()) continue;
    for (int dc = -2; dc <= 2; ++dc) {
      const int i = image.index(r + dr, (c + dc + image.cols()) % image.cols());
      if (i >= 0 && surfaces[static_cast<std::size_t>(i)] != s) return false;
    }
  }
  return true;
}

RoomLabels ClassifyRoom(const Eigen::Isometry3d& T_world_sensor, const Eigen::Matrix3d& R_given) {
  RoomLabels out;
  const SyntheticLidar lidar;
  out.scan = CastScan(lidar, BoxRoom(), T_world_sensor, &out.surfaces);
  RangeImage image(RangeImageConfig{}, lidar.Model());
  image.Build(out.scan.points, out.scan.rings);
  const NormalMap normals(image, NormalMapConfig{});
  const std::vector<PointClass> pixel_labels =
      Classifier(ClassifierConfig{}).Classify(normals, R_given);
  for (std::size_t i = 0; i < out.scan.size(); ++i) {
    const int pixel = image.pixel_of(i);
    out.labels.push_back(pixel_labels[static_cast<std::size_t>(pixel)]);
    out.world.push_back(T_world_sensor * out.scan.points[i]);
    out.interior.push_back(
        InteriorPixel(image, out.surfaces, pixel / image.cols(), pixel % image.cols()));
  }
  return out;
}

// Share of the interior points of each face (6 room faces) that carry the face's class.
std::array<double, 6> FaceAccuracy(const RoomLabels& room) {
  std::array<int, 6> total{}, right{};
  for (std::size_t i = 0; i < room.labels.size(); ++i) {
    const int s = room.surfaces[i];
    if (!room.interior[i]) continue;
    ++total[s];
    right[s] += room.labels[i] == ExpectedClass(s) ? 1 : 0;
  }
  std::array<double, 6> share{};
  for (int s = 0; s < 6; ++s) {
    EXPECT_GT(total[s], 200) << "face " << s << " barely seen; the scene is wrong";
    share[s] = total[s] > 0 ? double(right[s]) / total[s] : 0.0;
  }
  return share;
}

Eigen::Isometry3d SensorPose(const Eigen::Matrix3d& R) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = Eigen::Vector3d(0.6, -0.4, 1.4);
  return T;
}

TEST(Classifier, BoxRoomFacesGetTheirClass) {
  const RoomLabels room =
      ClassifyRoom(SensorPose(Eigen::Matrix3d::Identity()), Eigen::Matrix3d::Identity());
  const auto share = FaceAccuracy(room);
  for (int s = 0; s < 6; ++s) EXPECT_GT(share[s], 0.95) << "face " << s;
}

TEST(Classifier, WallWallCornersAreEdges) {
  const RoomLabels room =
      ClassifyRoom(SensorPose(Eigen::Matrix3d::Identity()), Eigen::Matrix3d::Identity());
  // In every ring and for each of the four vertical corners, the wall point nearest to the
  // corner line (at mid height, away from floor and ceiling).
  const test::AlignedBox box = BoxRoom().room;
  const std::array<Eigen::Vector2d, 4> corners = {
      Eigen::Vector2d(box.min.x(), box.min.y()), Eigen::Vector2d(box.min.x(), box.max.y()),
      Eigen::Vector2d(box.max.x(), box.min.y()), Eigen::Vector2d(box.max.x(), box.max.y())};
  std::map<std::pair<int, int>, std::pair<double, std::size_t>> nearest;  // (ring, corner)
  for (std::size_t i = 0; i < room.labels.size(); ++i) {
    const Eigen::Vector3d& p = room.world[i];
    if (room.surfaces[i] >= 4 || p.z() < 0.3 || p.z() > 2.7) continue;
    for (int k = 0; k < 4; ++k) {
      const double d = (p.head<2>() - corners[k]).norm();
      auto key = std::make_pair(int(room.scan.rings[i]), k);
      auto it = nearest.find(key);
      if (it == nearest.end() || d < it->second.first) nearest[key] = {d, i};
    }
  }
  int edges = 0, corners_seen = 0;
  for (const auto& [key, value] : nearest) {
    if (value.first > 0.1) continue;  // this ring meets the corner below 0.3 m or above 2.7 m
    ++corners_seen;
    edges += room.labels[value.second] == PointClass::Edge;
  }
  ASSERT_GT(corners_seen, 50);
  EXPECT_GT(double(edges) / corners_seen, 0.9);
  // And the wall interior is not littered with edges.
  std::size_t wall_edges = 0, wall_points = 0;
  for (std::size_t i = 0; i < room.labels.size(); ++i) {
    if (room.surfaces[i] >= 4 || !room.interior[i]) continue;
    ++wall_points;
    wall_edges += room.labels[i] == PointClass::Edge;
  }
  EXPECT_LT(double(wall_edges) / wall_points, 0.01);
}

// A VLP-16 at 10 Hz (16 rings over 30 deg, 0.2 deg columns) in a 2.4 m wide corridor with
// 1 cm range noise, as the sensor's datasheet states. Side-wall pixels a few metres away are a
// few millimetres apart, so a tangent must widen over many columns before the noise stops
// dominating its direction; a stencil capped too short turned half of such walls into edges
// (measured: 15.7k of 28k corridor points), and edge points matched point-to-point drag the
// corridor's free axis.
TEST(Classifier, NoisyCorridorWallsOfASparseSensorAreWalls) {
  Scene corridor;
  corridor.has_room = true;
  corridor.room = {{-40.0, -1.2, 0.0}, {40.0, 1.2, 2.8}};
  SyntheticLidar vlp16;
  vlp16.rings = 16;
  vlp16.cols = 1800;
  vlp16.top_deg = 15.0;
  vlp16.bottom_deg = -15.0;
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  T_world_sensor.translation() = Eigen::Vector3d(0.0, 0.3, 1.2);
  std::vector<int> surfaces;
  Scan scan = CastScan(vlp16, corridor, T_world_sensor, &surfaces);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (Eigen::Vector3d& p : scan.points) p *= 1.0 + noise(rng) / p.norm();

  RangeImage image(RangeImageConfig{}, vlp16.Model());
  image.Build(scan.points, scan.rings);
  const NormalMap normals(image, NormalMapConfig{});
  const std::vector<PointClass> labels =
      Classifier(ClassifierConfig{}).Classify(normals, Eigen::Matrix3d::Identity());
  int side_wall = 0, as_wall = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d p = T_world_sensor * scan.points[i];
    // Side walls (surfaces 2, 3: y = -1.2, y = 1.2) within 8 m and away from floor and ceiling.
    if ((surfaces[i] != 2 && surfaces[i] != 3) || std::abs(p.x()) > 8.0 || p.z() < 0.4 ||
        p.z() > 2.4) {
      continue;
    }
    ++side_wall;
    as_wall += labels[static_cast<std::size_t>(image.pixel_of(i))] == PointClass::Wall;
  }
  ASSERT_GT(side_wall, 3000);
  EXPECT_GT(double(as_wall) / side_wall, 0.9) << as_wall << " of " << side_wall;
}

TEST(Classifier, RolledSensorWithKnownOrientation) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(30.0 * kDeg, Eigen::Vector3d::UnitX()).matrix();
  const RoomLabels room = ClassifyRoom(SensorPose(R), R);
  const auto share = FaceAccuracy(room);
  for (int s = 0; s < 6; ++s) EXPECT_GT(share[s], 0.95) << "face " << s;
}

// Pitched down 60 deg, the floor's normal is mostly along the sensor's x axis: only the
// gravity-aligned frame tells it is the floor.
TEST(Classifier, PitchedFloorNeedsTheOrientation) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(60.0 * kDeg, Eigen::Vector3d::UnitY()).matrix();
  const RoomLabels with = ClassifyRoom(SensorPose(R), R);
  const RoomLabels without = ClassifyRoom(SensorPose(R), Eigen::Matrix3d::Identity());
  auto floor_share = [](const RoomLabels& room) {
    int total = 0, ground = 0;
    for (std::size_t i = 0; i < room.labels.size(); ++i) {
      if (room.surfaces[i] != 4 || !room.interior[i]) continue;
      ++total;
      ground += room.labels[i] == PointClass::Ground;
    }
    EXPECT_GT(total, 1000);
    return total > 0 ? double(ground) / total : 0.0;
  };
  EXPECT_GT(floor_share(with), 0.95);
  EXPECT_LT(floor_share(without), 0.05);
}

TEST(Classifier, WindowRules) {
  const Classifier classifier{ClassifierConfig{}};
  const Eigen::Vector3f up(0, 0, 1), down(0, 0, -1), side(0, 1, 0);
  auto window = [](std::initializer_list<Eigen::Vector3f> n) {
    return std::vector<Eigen::Vector3f>(n);
  };

  // 6 of 9 up would make ground, but the 90 deg spread is an edge first (mean angle 45 deg).
  auto w = window({up, up, up, up, up, up, side, side, side});
  EXPECT_EQ(classifier.ClassifyWindow(w.data(), 9, true), PointClass::Edge);
  // Ground with a slight tilt everywhere (10 deg): still ground, no edge.
  const Eigen::Vector3f tilted = Eigen::Vector3f(std::sin(0.17f), 0, std::cos(0.17f));
  w = window({up, up, up, up, up, up, tilted, tilted, tilted});
  EXPECT_EQ(classifier.ClassifyWindow(w.data(), 9, true), PointClass::Ground);
  w = window({down, down, down, down});
  EXPECT_EQ(classifier.ClassifyWindow(w.data(), 4, true), PointClass::Roof);
  w = window({side, side, side, side, side});
  EXPECT_EQ(classifier.ClassifyWindow(w.data(), 5, true), PointClass::Wall);
  // Too few valid normals.
  EXPECT_EQ(classifier.ClassifyWindow(w.data(), 3, true), PointClass::Unknown);
  // The centre's own normal is missing: no planar class.
  EXPECT_EQ(classifier.ClassifyWindow(w.data(), 5, false), PointClass::Unknown);
  // A 45 deg slope split 50/50 between "z dominant" and "x dominant" normals: no 2/3 majority.
  const Eigen::Vector3f a = Eigen::Vector3f(0.68f, 0, 0.73f), b = Eigen::Vector3f(0.73f, 0, 0.68f);
  w = window({a, b, a, b, a, b});
  EXPECT_EQ(classifier.ClassifyWindow(w.data(), 6, true), PointClass::Unknown);
}

}  // namespace
}  // namespace dammloam
