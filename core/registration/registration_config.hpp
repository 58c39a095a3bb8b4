#pragma once
#include <optional>
#include <string_view>

namespace dammloam {

// Which residuals the registration uses. kFull is the paper's method; the others are the
// ablations of the benchmark.
enum class RegistrationMode {
  kFull,                 // class-wise pt2pl/pt2pt, alpha, degeneracy weights, remapping
  kPointToPoint,         // every point point-to-point, any class (KISS-ICP-like)
  kPlaneOnly,            // every point point-to-plane against the map normal, any class
  kClassesNoDegeneracy,  // class-wise pt2pl/pt2pt with alpha, all weights 1
};

std::string_view Name(RegistrationMode mode);
std::optional<RegistrationMode> ParseRegistrationMode(std::string_view name);

struct RegistrationConfig {
  RegistrationMode mode = RegistrationMode::kFull;
  int max_iterations = 50;
  double convergence_criterion = 5e-4;  // |dx| (m, rad) below which Gauss-Newton stops
  // KISS-ICP adaptive threshold: correspondence gate = 3 sigma of the model deviation history,
  // robust kernel scale = sigma / 3.
  double initial_threshold = 2.0;       // metres, sigma before any history exists
  double min_motion_threshold = 0.1;    // metres; smaller deviations do not teach the threshold
  // A translational direction is degenerate when lambda_i / lambda_max of the planar H_tt is
  // below this. The free axis of a VLP-16 corridor with its end walls 20-40 m away sits at
  // 0.004-0.005; at 0.02 a corridor still seeing its end wall nearby was flagged, and the
  // remapping froze a velocity the walls could still have corrected (dammloam-bench-odometry).
  double degenerate_eigenvalue_ratio = 0.005;
  // Hysteresis, applied by the odometry: after a degenerate scan a direction counts as
  // degenerate until its ratio exceeds this. A direction hovering at the threshold would
  // otherwise be released for single scans whose weak, ring-biased information then kicks the
  // held velocity (a 200 m OS1-64 corridor ended at twice its true speed).
  double degenerate_release_ratio = 0.02;
  // Full mode: translation updates along degenerate directions are dropped, so the estimate
  // keeps the constant-velocity prediction there (solution remapping), once the motion model
  // has held (see OdometryConfig::motion_model_max_deviation).
  bool remap_degenerate_directions = true;
  // Full mode: degeneracy weights apply on every scan, not only where a direction is
  // degenerate (the paper applies them always; in well-conditioned scenes they only remove
  // information, measured by dammloam-bench-odometry).
  bool weight_always = false;
  // Full mode: point residuals are weighted per eigen-direction like planar normals, so edge
  // and unknown points cannot pin a direction the planes leave weak.
  bool weight_point_residuals = true;
  // Class-wise modes: an `unknown` source point (the scan could not judge its surface, as on a
  // far wall two rings tall) matches the nearest map point of any class and takes that point's
  // residual: point-to-plane on a map plane, seen nearer and better, point-to-point otherwise.
  // Off, it only matches unknown map points, and a VLP-16 corridor loses the far end walls
  // that are the only constraint along its axis.
  bool unknown_defers_to_map = true;
  int min_correspondences = 30;         // fewer: the scan is not registered
  double covariance_regularisation = 1e-6;  // relative to trace(H)/6, keeps H invertible
};

constexpr bool ClassWise(RegistrationMode m) {
  return m == RegistrationMode::kFull || m == RegistrationMode::kClassesNoDegeneracy;
}
constexpr bool UsesDegeneracyWeights(RegistrationMode m) { return m == RegistrationMode::kFull; }

}  // namespace dammloam
