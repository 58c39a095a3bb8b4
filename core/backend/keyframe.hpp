#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/backend/scan_context.hpp"
#include "core/geometry/point_class.hpp"
#include "core/geometry/se3.hpp"

namespace dammloam::backend {

// One keyframe: a downsampled, labelled cloud in its own sensor frame, its odometry pose and
// the pose the pose graph assigns to it after loop closures.
struct Keyframe {
  std::uint32_t id = 0;                 // dense, 0..N-1 in insertion order
  std::uint64_t scan_index = 0;         // OdometryResult::scan_index it was taken from
  double stamp = 0.0;                   // seconds
  Eigen::Isometry3d T_world_sensor_odom = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();  // corrected
  // Covariance of the odometry edge from the previous keyframe to this one, tangent [t; r].
  Matrix6d edge_covariance = Matrix6d::Identity();
  std::vector<Eigen::Vector3d> points;  // sensor frame
  std::vector<PointClass> labels;       // empty or one per point
  // Points the front end judged moving, sensor frame, thinned like `points`: never mapped, but
  // they stood in the way of this keyframe's beams (vacated_points.hpp). Not saved.
  std::vector<Eigen::Vector3d> occluders;
  ScanContext descriptor;
};

// A loop constraint that passed verification: T_from_to maps `to`'s frame into `from`'s.
struct LoopConstraint {
  std::uint32_t from = 0;
  std::uint32_t to = 0;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
};

// Everything a saved map holds; produced by LoopClosingBackend::ExportMap(), consumed by
// Localizer and by the map store in io/mapstore.
struct MapData {
  ScanContextConfig scan_context;       // descriptors are only comparable under one config
  std::vector<Keyframe> keyframes;
  std::vector<LoopConstraint> loops;
  // Global labelled map in the world frame (voxel-downsampled union of keyframe clouds).
  std::vector<Eigen::Vector3d> global_points;
  std::vector<PointClass> global_labels;
  // Points the keyframes hold that later ones saw through, left out of global_points (not saved).
  std::size_t vacated_points = 0;
};

}  // namespace dammloam::backend
