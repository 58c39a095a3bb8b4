#pragma once
#include "core/backend/keyframe.hpp"
#include "core/backend/loop_event.hpp"
#include "core/backend/point_to_plane_icp.hpp"
#include "core/backend/scan_context.hpp"

namespace dammloam::backend {

struct LoopVerifierConfig {
  IcpConfig icp;
  // Overlap needed from the registration started at Scan Context's guess; one started at
  // odometry's guess that stays within the drift budget has odometry's word for it and may
  // overlap less (keyframes metres apart in a corridor share ~45% of their points).
  double min_inlier_ratio = 0.6;
  double min_inlier_ratio_from_odometry = 0.4;
  double max_rmse = 0.12;                // metres
  // The registered relative pose may disagree with odometry by at most
  // drift_per_metre * path length between the keyframes + drift_offset: this rejects look-alike
  // places (repetitive corridors) whose true separation odometry knows to be large.
  double drift_per_metre = 0.05;
  double drift_offset = 1.0;             // metres
  int normal_neighbours = 10;
  // The relative rotation may disagree with odometry by at most this much.
  double rotation_drift_per_metre = 0.005;  // radians per metre of path
  double rotation_drift_offset = 0.1;       // radians
  // A translation direction counts as observed when the inlier normals hold at least this many
  // points' worth of support along it. A loop must observe min_observed_directions of them; a
  // corridor loop observes two and constrains the pose graph only across the corridor (the
  // ICP information along the axis is a few far points at grazing angles: not to be trusted).
  double min_direction_support = 25.0;
  int min_observed_directions = 2;
  double min_noise_sigma = 0.02;         // floor on the residual RMS used as noise, metres
  // Weak priors that keep the loop's information invertible along free directions.
  double free_translation_sigma = 100.0; // metres
  double free_rotation_sigma = 1.0;      // radians
  // A loop that puts the query more than this far above or below the candidate (vertically in
  // the map's frame; along directions the registration does not observe, as odometry puts it)
  // joins two levels of a building: a storey up, the walls of a floor plan repeated on every
  // floor fit as well as the same floor's would, and a ground robot or a walker never revisits
  // a place at another height. 0: not checked.
  double max_level_difference = 1.5;     // metres

  bool operator==(const LoopVerifierConfig&) const = default;
};

// Registers a Scan Context candidate pair with point-to-plane ICP and decides whether it is a
// real loop; an accepted loop carries its covariance from the registration's information, so
// a partly degenerate loop constrains only what it observes. Stateless apart from its config,
// so it may run on any thread.
class LoopVerifier {
 public:
  explicit LoopVerifier(const LoopVerifierConfig& config = {}) : config_(config) {}

  // path_length: odometry distance travelled from `candidate` to `query`.
  LoopEvent Verify(const Keyframe& query, const Keyframe& candidate,
                   const ScanContextMatch& match, double path_length) const;

 private:
  // Fills `event` from one registration (`observed`: projector onto the translation
  // directions it fixes) and decides on it.
  // R_map_candidate: the candidate's orientation in the map (which way is up).
  void Judge(const IcpResult& icp, const Eigen::Matrix3d& observed,
             const Eigen::Isometry3d& T_odom, const Eigen::Matrix3d& R_map_candidate,
             double path_length, double min_inlier_ratio, LoopEvent& event) const;

  LoopVerifierConfig config_;
};

}  // namespace dammloam::backend
