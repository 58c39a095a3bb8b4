#pragma once
// What the bridge serves, converted from dammloamd's DDS samples into the bytes of the Foxglove
// channels: ROS 2 CDR (io/bag's encoders and ros2msg schemas, as the MCAP output writes them)
// for odometry, tf, clouds and loop lines; JSON for the status. Pure functions and small
// accumulators, so the tests can check them without sockets.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/cloud/point_cloud2.hpp"
#include "dammloam.h"
#include "tools/bridge/foxglove_protocol.hpp"

namespace dammloam::bridge {

// Channel ids are fixed so that a reconnecting client sees the same table.
enum ChannelId : std::uint32_t {
  kOdometryChannel = 1,
  kTfChannel = 2,
  kLabelledCloudChannel = 3,
  kMapChannel = 4,
  kLoopClosureChannel = 5,
  kStatusChannel = 6,
  kTrajectoryChannel = 7,  // MarkerArray: the whole path so far, for clients that join late
};
std::vector<Channel> BridgeChannels();

// One point of a served cloud: map frame, dammloam point class (core/geometry/point_class.hpp).
struct ClassPoint {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  std::uint8_t label = 0;
};

std::uint64_t StampNanoseconds(const dammloam_msg_Time& stamp);

// nav_msgs/Odometry (pose, ROS-order covariance, twist) and tf2_msgs/TFMessage (map -> sensor).
std::string OdometryCdr(const dammloam_msg_Odometry& odometry);
std::string TfCdr(const dammloam_msg_Odometry& odometry);

// The map-frame points and labels of a LabelledCloud (fields map_x map_y map_z float32, label
// uint8), every stride-th point so that at most `budget` come out (budget 0 = all). Throws
// std::invalid_argument naming the problem for a cloud without those fields or whose data is
// shorter than its size says.
std::vector<ClassPoint> LabelledMapPoints(const dammloam_msg_LabelledCloud& cloud,
                                          std::size_t budget);
// sensor_msgs/PointCloud2 with fields x y z (float32) and label (uint8), point_step 16.
std::string ClassCloudCdr(const std::vector<ClassPoint>& points, const CloudStamp& stamp,
                          const std::string& frame_id);

// The map as voxels: the first point seen in each voxel, its label the newest one's (a wall
// point later seen as moving shows as moving). At most max_points voxels: once full, new voxels
// are counted and left out, so memory is bounded on any drive.
struct MapConfig {
  double voxel_size = 0.25;          // metres
  std::size_t max_points = 400'000;  // ~16 bytes each on the wire
};
class VoxelMap {
 public:
  explicit VoxelMap(const MapConfig& config = {}) : config_(config) {}
  void Add(const std::vector<ClassPoint>& points);
  std::vector<ClassPoint> Points() const;
  std::size_t size() const { return voxels_.size(); }
  std::uint64_t left_out() const { return left_out_; }

 private:
  MapConfig config_;
  std::unordered_map<std::uint64_t, ClassPoint> voxels_;
  std::uint64_t left_out_ = 0;
};

// Accepted loop closures as lines between the two keyframes' positions, found from the poses
// seen on the odometry topic by stamp. Bounded: the oldest poses and lines go first.
class LoopLines {
 public:
  void AddPose(std::uint64_t stamp_ns, const Eigen::Vector3d& position);
  // False when the loop was rejected or a keyframe's pose was never seen.
  bool AddLoop(const dammloam_msg_LoopClosure& loop);
  // visualization_msgs/MarkerArray with one LINE_LIST marker holding every accepted loop.
  std::string MarkerArrayCdr(const CloudStamp& stamp, const std::string& frame_id) const;
  std::size_t lines() const { return lines_.size(); }

 private:
  std::map<std::uint64_t, Eigen::Vector3d> positions_;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines_;
};

// The status channel's JSON: the daemon's DaemonStatus and the bridge's own counters.
struct BridgeCounters {
  std::size_t clients = 0;
  std::uint64_t frames_dropped = 0;  // over all clients since start
  std::size_t map_points = 0;
  std::uint64_t bad_samples = 0;     // DDS samples the bridge could not convert
};
std::string StatusJsonPayload(const dammloam_msg_DaemonStatus& status,
                              const BridgeCounters& bridge);

}  // namespace dammloam::bridge
