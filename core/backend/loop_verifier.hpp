#pragma once
#include "core/backend/keyframe.hpp"
#include "core/backend/loop_event.hpp"
#include "core/backend/point_to_plane_icp.hpp"
#include "core/backend/scan_context.hpp"

namespace dammloam::backend {

struct LoopVerifierConfig {
  IcpConfig icp;
  double min_inlier_ratio = 0.6;
  double max_rmse = 0.12;                // metres
  // The registered relative pose may disagree with odometry by at most
  // drift_per_metre * path length between the keyframes + drift_offset: this rejects look-alike
  // places (repetitive corridors) whose true separation odometry knows to be large.
  double drift_per_metre = 0.05;
  double drift_offset = 1.0;             // metres
  int normal_neighbours = 10;
  // Below this the registration cannot fix some translation direction: reject. Measured on the
  // simulator: featureless corridor loops 0.016-0.068, outdoor loops >= 0.17.
  double min_translation_observability = 0.1;
};

// Registers a Scan Context candidate pair with point-to-plane ICP and decides whether it is a
// real loop. Stateless apart from its config, so it may run on any thread.
class LoopVerifier {
 public:
  explicit LoopVerifier(const LoopVerifierConfig& config = {}) : config_(config) {}

  // path_length: odometry distance travelled from `candidate` to `query`.
  LoopEvent Verify(const Keyframe& query, const Keyframe& candidate,
                   const ScanContextMatch& match, double path_length) const;

 private:
  LoopVerifierConfig config_;
};

}  // namespace dammloam::backend
