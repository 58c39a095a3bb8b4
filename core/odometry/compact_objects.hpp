#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/geometry/point_class.hpp"

namespace dammloam {

// Small things standing on the ground (a person, a group, a cart, a bin), found per scan, and
// the rule that keeps them from holding a direction the rest of the scan does not observe.
//
// In a featureless corridor the only surfaces facing the axis may be a person's front and back.
// A person walking beside or ahead of the sensor at its pace then holds the estimate still
// along the axis, and a person who stood a moment entered the map and is matched later against
// their own body, which they hide from every later view (issue 52, handheld-corridor-people
// seed 2, follow-me). No test of seen-through space catches what moves with the sensor. What
// does: such objects are not allowed to be the axis' main witness. Where the rest of the scan
// observes that direction well, they stay in (a parked car outdoors is a good landmark, and
// the robust kernel takes care of one that drives off).
struct CompactObjectsConfig {
  // Off by default: measured on the people presets it helps some walks and not others (README).
  bool enabled = false;
  double cell = 0.25;        // metres: a horizontal grid; occupied neighbours are one object
  double max_range = 25.0;   // metres from the sensor, horizontally: farther is not judged
  // An object is compact when its footprint's diagonal is at most max_extent (a person is
  // 0.45 m, three walking abreast about 2 m), its top at most max_height above the ground (a
  // wall or a pillar seen whole reaches higher) and its lowest point seen at most max_lift
  // above it: it stands there, not hangs under a ceiling. The lift is generous because near
  // objects are seen only from the lowest beam up: a VLP-16 held at 1.4 m meets a person 2 m
  // away at 0.86 m, 1 m away at 1.13 m.
  double max_extent = 2.5;   // metres
  double max_lift = 1.2;     // metres
  double max_height = 2.3;   // metres
  double min_height = 0.5;   // metres seen from its lowest to its highest point
  int min_ground_points = 20;  // ground points within ground_reach that fix the ground height
  double ground_reach = 8.0;   // metres
  // The rest of the scan observes its weakest translation weakly when that eigenvalue of its
  // translational information (sum of n n^T) is below weak_axis_ratio of the largest; the
  // objects facing it are then set aside when they add at least witness_share of the rest's
  // information there. 0: whatever they add. In a featureless corridor the rest's weak
  // eigenvalue is mostly wall noise that pins nothing, so even a far person, consistent from
  // scan to scan, steers the axis: at 0.5 one walking away 8 m behind set the velocity to twice
  // the walk's, and the motion model kept it (handheld-corridor-people seed 1: 88 m APE, at 0:
  // 0.02 m).
  double weak_axis_ratio = 0.1;
  double witness_share = 0.0;
  // A point faces a direction when |n . d| is at least this (60 deg off at most).
  double facing_cos = 0.5;
  // The rest of an object's body (a person's sides, corners, shoulders) is what lies within
  // body_depth of its facing points along the direction, body_margin across it and up to
  // body_margin above its top: kept in, the sides would enter the map as a trail whose corners
  // hold the estimate back.
  double body_depth = 0.6;   // metres
  double body_margin = 0.1;  // metres
  // Seconds that what would witness a weak axis (MapLater) must keep its place before it
  // enters the map, with moving.map_after (which the rest needs). 0: no longer than the rest.
  // A group that waits beside the path for two seconds and then walks on at the walker's pace
  // otherwise enters the map and is matched against its own old bodies: the estimate stands
  // still with it (handheld-corridor-people seed 2: 21 m APE; at 3 s 0.0125 m). Off by default:
  // at 3 s the person walking ahead in follow-me takes the estimate with them (1.3 -> 57 m).
  double map_after = 0.0;    // seconds
  // A wall near the sensor is seen only up to the highest beam, so it looks as short as a
  // person: an object whose highest point lies within top_margin_deg of the highest elevation
  // any point of the scan has may go on above the view and is not judged compact (a short
  // wall facet at a zigzag corridor's bend, which alone observes the axis there, was set aside:
  // wheeled-zigzag seed 2 APE 0.0077 -> 0.0128 m).
  double top_margin_deg = 1.0;
};

class CompactObjects {
 public:
  explicit CompactObjects(const CompactObjectsConfig& config) : config_(config) {}

  // 1 per point of points_sensor on a compact object that faces `direction` (sensor frame,
  // unit), else 0 (empty: the ground height is unknown, nothing judged). Only the points whose
  // normal faces that direction are grouped: a person's front, not the wall they walk beside,
  // which would otherwise join them into one long structure. R_world_sensor turns the scan
  // upright (only its rotation is used).
  const std::vector<std::uint8_t>& Find(const std::vector<Eigen::Vector3d>& points_sensor,
                                        const std::vector<PointClass>& labels,
                                        const std::vector<Eigen::Vector3f>& normals,
                                        const Eigen::Vector3d& direction,
                                        const Eigen::Matrix3d& R_world_sensor);

 private:
  struct Cell {
    float z_min, z_max;
    int object;  // -1: empty; else an index into objects_
  };
  struct Object {
    Eigen::Vector2f lo, hi;  // cell indices
    float z_min, z_max;
    bool compact;
    // Of a compact object's facing points: extent along and across the direction (horizontal).
    float along_min, along_max, across_min, across_max;
    float elevation_max;  // of its facing points, sensor frame (radians)
  };
  bool GroundHeight(const std::vector<Eigen::Vector3d>& upright,
                    const std::vector<PointClass>& labels, float& ground);
  void Label(int start);
  // Marks the points within the bodies of the compact objects (mask_ holds their facing points).
  void MarkBodies(const Eigen::Vector2d& along, const Eigen::Vector2d& across, float ground);

  CompactObjectsConfig config_;
  int side_ = 0;                      // cells per side of the grid centred on the sensor
  std::vector<Cell> cells_;
  std::vector<int> occupied_, stack_, pixel_;  // pixel_: each point's cell, -1 if not judged
  std::vector<Object> objects_;
  std::vector<Eigen::Vector3d> upright_;
  std::vector<float> ground_z_;
  std::vector<std::uint8_t> mask_;
  std::vector<std::uint8_t> judged_;  // per point: neither ground nor roof
};

// The direction (sensor frame, unit) that the indexed points' normals observe least, and how
// weakly: its eigenvalue of sum n n^T over the largest.
struct WeakestAxis {
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  double share = 1.0;
};
WeakestAxis WeakestAxisOf(const std::vector<Eigen::Vector3f>& normals,
                          const std::vector<std::size_t>& indices);

// Per point, 1 where the map should take it only after config.map_after: on a compact object
// (object_mask), or, where the scan observes `weakest` below weak_axis_ratio of its strongest
// direction, a point that would witness that direction (its normal faces it, or an edge, which
// is registered point to point). Those few points hold a featureless corridor's axis, and a
// group that stood for two seconds and then walks along must not be among them; a door frame
// seen as the walker approaches it is seen for longer.
std::vector<std::uint8_t> MapLater(const std::vector<PointClass>& labels,
                                   const std::vector<Eigen::Vector3f>& normals,
                                   const WeakestAxis& weakest,
                                   const std::vector<std::uint8_t>& object_mask,
                                   const CompactObjectsConfig& config);

Eigen::Vector3d WeakestDirection(const std::vector<Eigen::Vector3f>& normals,
                                 const std::vector<std::size_t>& indices);

// Whether the compact objects' points (object_mask, per point) are the main witnesses of the
// direction the rest of `indices` observes least, by the points' normals (zero: no planar
// information): true means registering them would let them hold that direction.
bool ObjectsWitnessTheWeakAxis(const std::vector<Eigen::Vector3f>& normals,
                               const std::vector<std::size_t>& indices,
                               const std::vector<std::uint8_t>& object_mask,
                               const CompactObjectsConfig& config);

}  // namespace dammloam
