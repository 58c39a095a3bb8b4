#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/geometry/se3.hpp"

namespace dammloam::backend {

struct PoseGraphConfig {
  // Loop edges are under a Huber loss (scale in whitened units): its bounded pull cannot drag
  // the map far, yet unlike Cauchy it never drops a true loop whose drift the (usually
  // over-confident) odometry covariances make look large.
  double loop_huber_scale = 1.0;
  // After optimising, a loop still disagreeing by more than this (whitened norm) is switched
  // off and the graph re-solved without it, so a false loop keeps no pull on the map at all.
  double loop_prune_threshold = 10.0;
  int max_prune_rounds = 3;  // each round re-solves the graph, worst loop first
  int max_iterations = 100;
  // Floors on odometry edge standard deviations (per keyframe edge, ~1 m), for scans whose
  // registration covariance is far too confident. Scan-to-map odometry between two keyframes is
  // rarely worse than this; at 2 cm / 0.002 rad a 150 m chain counted as 24 cm uncertain, and
  // a loop with 2 cm of registration noise pulled a trajectory good to 6 mm.
  double min_translation_sigma = 0.002;  // metres
  double min_rotation_sigma = 0.0002;    // radians

  bool operator==(const PoseGraphConfig&) const = default;
};

struct PoseGraphSummary {
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double solve_ms = 0.0;
  int rejected_loops = 0;  // loops switched off as inconsistent by this Optimize()
};

// SE(3) pose graph solved with Ceres: each node a position + unit quaternion (quaternion
// manifold); odometry edges weighted by their inverse covariance, loop edges additionally under
// a Huber loss and pruned when inconsistent, so a single wrong loop cannot wreck the map.
// Node 0 is held fixed.
class PoseGraph {
 public:
  explicit PoseGraph(const PoseGraphConfig& config = {}) : config_(config) {}

  std::uint32_t AddNode(const Eigen::Isometry3d& T_world_node);
  // T_from_to: pose of `to` in `from`'s frame; covariance in tangent order [t; r].
  void AddOdometryEdge(std::uint32_t from, std::uint32_t to, const Eigen::Isometry3d& T_from_to,
                       const Matrix6d& covariance);
  void AddLoopEdge(std::uint32_t from, std::uint32_t to, const Eigen::Isometry3d& T_from_to,
                   const Matrix6d& covariance);

  // Takes back the edge added last (a loop that turned out to agree with the map).
  void RemoveLastEdge();

  PoseGraphSummary Optimize();

  std::size_t NumNodes() const { return nodes_.size(); }
  std::size_t NumLoopEdges() const;
  // Loop edges currently switched off as inconsistent.
  std::size_t NumRejectedLoops() const;
  // Whitened residual norm of every loop edge at the current poses, in insertion order.
  std::vector<double> LoopResiduals() const;
  // Whitened residual norm of the edge added last, at the current poses.
  double LastEdgeResidual() const;
  Eigen::Isometry3d Pose(std::uint32_t id) const;
  void SetPose(std::uint32_t id, const Eigen::Isometry3d& T_world_node);

 private:
  struct Node {
    double position[3];
    double quaternion[4];  // x, y, z, w (Eigen's storage order)
  };
  struct Edge {
    std::uint32_t from, to;
    Eigen::Vector3d t;
    Eigen::Quaterniond q;
    Matrix6d sqrt_information;
    bool loop;
    bool active = true;
  };
  void AddEdge(std::uint32_t from, std::uint32_t to, const Eigen::Isometry3d& T_from_to,
               const Matrix6d& covariance, bool loop);
  // One Ceres solve over the active edges.
  void Solve(PoseGraphSummary& summary);
  double WhitenedNorm(const Edge& e) const;

  PoseGraphConfig config_;
  std::vector<Node> nodes_;
  std::vector<Edge> edges_;
};

}  // namespace dammloam::backend
