#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <vector>

#include "core/geometry/depth_view.hpp"
#include "core/geometry/point_class.hpp"
#include "core/geometry/scan.hpp"
#include "core/map/voxel_hash_map.hpp"

namespace dammloam {

struct MovingPointsConfig {
  bool enabled = false;
  // Past scans whose views a point is tested against, by age in seconds: space a person or a
  // car now fills was seen through half a second or a second ago, from nearly the same place.
  std::vector<double> view_ages = {0.5, 1.0};
  // A point is in seen-through space when the past returns around its direction lie this much
  // beyond it: above range noise, pose error and the thickness of a surface at grazing angles.
  double margin = 0.3;              // metres
  double margin_per_metre = 0.03;   // plus this share of its distance from the past sensor
  double max_range = 40.0;          // metres from the sensor; farther points are not judged
  // Evidence spreads over the object it belongs to: points closer than cluster_spacing are one
  // object; an object with at least min_evidence points (and min_evidence_share of its points)
  // seen through moves as a whole, unless it is larger than an actor (a wall a person stands
  // against), where only the points seen through are taken.
  double cluster_spacing = 0.25;    // metres
  int min_evidence = 3;
  double min_evidence_share = 0.2;
  double max_object_extent = 6.0;   // metres, horizontal
  // Something walking away along the line of sight stands where a past scan could not look (its
  // own earlier body hid the place). Its evidence is the space it vacated: past points the scan
  // now sees through. A point counts when it was hidden then, lies within vacated_reach of such
  // vacated space, is not explained by the map (no map point within unmapped_distance), and
  // belongs to a compact object (never a wall it stands in front of).
  double vacated_reach = 2.0;       // metres: walking speed times the oldest view age, and a body
  double unmapped_distance = 0.3;   // metres
  double vacated_sample = 0.15;     // metres: past points kept per cell of this size, for the test
  // A place enters the map only after scans have found a surface there for this long (seconds;
  // 0: at once): what walks through, or ahead of the sensor, never does (PersistenceFilter).
  double map_after = 0.5;
  double map_after_max_gap = 0.35;  // seconds without a point there that start it over
  DepthView::Config view;
};

// Which points of a scan lie on things that move: a point is moving when a recent scan saw
// through the place where it is now, and so is the rest of the compact object it belongs to.
// Ground and roof points are never moving (a floor under a walking person is seen through at
// grazing angles by no ray, but nothing is gained by testing it).
class MovingPoints {
 public:
  MovingPoints(const MovingPointsConfig& config, const SensorModel& sensor);

  // 1 per moving point of points_sensor (the scan in the frame of T_world_sensor, taken at
  // `stamp`), else 0. `map` (optional): the local map, which explains static surfaces that
  // were hidden from the past views.
  std::vector<std::uint8_t> Detect(const std::vector<Eigen::Vector3d>& points_sensor,
                                   const std::vector<PointClass>& labels,
                                   const Eigen::Isometry3d& T_world_sensor, double stamp,
                                   const VoxelHashMap* map = nullptr) const;
  // Remembers a registered scan's view and a sample of its points that can move; views older
  // than the oldest age tested are dropped.
  void AddView(const std::vector<Eigen::Vector3d>& points_sensor,
               const std::vector<PointClass>& labels, const Eigen::Isometry3d& T_world_sensor,
               double stamp);
  // The newest view, for the map's removal of what has since moved away; nullptr before any.
  const DepthView* newest_view() const { return views_.empty() ? nullptr : &views_.back().view; }
  double Margin(double distance) const { return config_.margin + config_.margin_per_metre * distance; }
  void Clear() { views_.clear(); }

 private:
  struct StampedView {
    double stamp;
    DepthView view;
    std::vector<Eigen::Vector3d> sample_world;  // points that can move, one per vacated_sample cell
  };
  // Evidence bits: the point sits where a past view saw through (kSeenThrough); it was hidden
  // from a past view and stands next to space vacated since (kNextToVacated).
  static constexpr std::uint8_t kSeenThrough = 1, kNextToVacated = 2;
  // The views Detect tests: for each age, the newest view at least that old.
  std::vector<const StampedView*> ViewsToTest(double stamp) const;
  std::vector<std::uint8_t> Evidence(const std::vector<Eigen::Vector3d>& points_sensor,
                                     const std::vector<PointClass>& labels,
                                     const Eigen::Isometry3d& T_world_sensor,
                                     const std::vector<const StampedView*>& views) const;
  // Adds kNextToVacated to the points of `evidence` it applies to.
  void NextToVacated(const std::vector<Eigen::Vector3d>& points_sensor,
                     const std::vector<PointClass>& labels, const Eigen::Isometry3d& T_world_sensor,
                     const std::vector<const StampedView*>& views, const VoxelHashMap& map,
                     std::vector<std::uint8_t>& evidence) const;
  void SpreadOverObjects(const std::vector<Eigen::Vector3d>& points_sensor,
                         const std::vector<PointClass>& labels,
                         std::vector<std::uint8_t>& moving) const;

  MovingPointsConfig config_;
  SensorModel sensor_;
  std::deque<StampedView> views_;
};

// Points that can be judged at all: not ground, not roof.
constexpr bool CanMove(PointClass c) { return c != PointClass::Ground && c != PointClass::Roof; }

}  // namespace dammloam
