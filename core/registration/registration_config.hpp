#pragma once
#include <optional>
#include <string_view>

namespace dammloam {

// Which residuals the registration uses. kFull is the paper's method; the others are the
// ablations of the benchmark.
enum class RegistrationMode {
  kFull,                 // class-wise pt2pl/pt2pt, alpha, weak directions fused with the motion prior
  kFullRemap,            // class-wise, alpha, the paper's degeneracy weights, solution remapping
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
  // full_remap mode: translation updates along degenerate directions are dropped, so the estimate
  // keeps the constant-velocity prediction there (solution remapping), once the motion model
  // has held (see OdometryConfig::motion_model_max_deviation).
  bool remap_degenerate_directions = true;
  // full_remap mode: degeneracy weights apply on every scan, not only where a direction is
  // degenerate (the paper applies them always; in well-conditioned scenes they only remove
  // information, measured by dammloam-bench-odometry).
  bool weight_always = false;
  // full_remap mode: point residuals are weighted per eigen-direction like planar normals, so edge
  // and unknown points cannot pin a direction the planes leave weak.
  bool weight_point_residuals = true;
  // Class-wise modes: an `unknown` source point (the scan could not judge its surface, as on a
  // far wall two rings tall) matches the nearest map point of any class and takes that point's
  // residual: point-to-plane on a map plane, seen nearer and better, point-to-point otherwise.
  // Off, it only matches unknown map points, and a VLP-16 corridor loses the far end walls
  // that are the only constraint along its axis.
  bool unknown_defers_to_map = true;
  // Full mode (the motion prior): along a direction the planes leave weak, a planar pair counts
  // only if its normal's cosine to the direction is at least this (a door jamb, an end wall, a
  // lamp face). Walls along a corridor carry a few per cent of their normal's noise along the
  // axis, and with thousands of them that noise would outweigh the prior.
  double strong_normal_cosine = 0.5;
  // Full mode, along a weak direction: a point pair whose target's map neighbourhood (27 voxels)
  // has lambda_min / sum(lambda) below this lies on a plane and becomes point-to-plane; with the
  // middle eigenvalue below it too, on a line (point-to-line). Point pairs on a wall follow the
  // ring pattern and report standstill: counted as points, a hand-held VLP-16 walk stuck where
  // it had stopped on the way out and ran away elsewhere (0.43 / 75.7 m APE on seeds 2 / 3).
  double point_flatness = 0.1;
  // Full mode: judge point pairs by their map neighbourhood's shape (as above) on every scan,
  // not only on scans with a weak direction. A point pair on a plane then counts as
  // point-to-plane wherever it is: paired with the few first-sighting points a voxel keeps, it
  // otherwise follows their sampling pattern. Measured (docs/measurements.md, 2026-11-28): the
  // VLP-16 zigzag's forward drift of ~0.1 % of the distance falls (APE -9 to -28 % on every
  // seed, RPE -1 to -3 %), campus APE -22 %, hand-held and tunnels within a few per cent
  // either way; the wheeled VLP-16 corridor loses 0-15 % APE. false: judged only on scans with
  // a weak direction (the release of 2026-11-27).
  bool judge_point_pairs_always = true;
  // Full mode: a neighbourhood of fewer map points than this is not judged (its pair stays a
  // point pair). A young map's neighbourhoods hold one ring or two: a single ring on a wall
  // fits a line facing up, a ring on the floor next to one on a wall a tilted plane, and, taken
  // for surfaces at the planes' weight, they dragged the height with the ring pattern wherever
  // the height was the weak direction (first 3 s of the hand-held VLP-16 corridor: vertical
  // frame error 3.3 cm, against 1.9 cm later in the walk).
  int point_shape_min_points = 20;
  // Full mode: a line-shaped neighbourhood keeps a normal only where the map points there face
  // it (mean of (n . n_point)^2 over their stored normals at least this). Far from the sensor a
  // neighbourhood holds one ring's arc across a floor, a ceiling or a wall: a line of a plane,
  // whose second normal lies in the plane. On the floor ahead it faces the corridor's axis, and
  // bobbing moves each ring's arc along the axis: a sensor at rest at the start of the 460 m
  // endless corridor ran backwards at 2 m/s from its sixth scan (OS1-64 seed 2). Such a line
  // counts as the plane its points face. Corners, jambs and pipes, whose points face both
  // normals, keep both. 0: every line keeps both normals.
  double line_normal_support = 0.1;
  // Full mode: a direction is weak, and its pairs are sorted as above, when lambda_i /
  // lambda_max of the planar H_tt is below this. Sorting costs a direction nothing that facing
  // pairs observe, so the bar is higher than for the paper's weights: a corridor still seeing a
  // far end wall sits at 0.008-0.015, where the walls' normal noise would otherwise slide the
  // estimate along the axis (1.7 m in one scan on the hand-held OS1-64 corridor).
  double weak_eigenvalue_ratio = 0.05;
  // Full mode: 1-sigma noise of one pair's residual (range noise of scan and map, surface
  // roughness): turns the data's normal equations into information in absolute units, so that
  // they weigh against the motion prior's.
  double residual_sigma = 0.02;
  // After a Gauss-Newton step that moved no source point farther than this (metres), the next
  // iteration keeps its pairs and only moves their source points: a nearest map point (map
  // points lie voxel/sqrt(3) apart or more) does not change under a millimetre step, and the
  // search is most of the registration's cost. 0: search on every iteration.
  double correspondence_reuse_distance = 0.01;
  // A step after a fresh search that repeats the previous step's direction is stretched by
  // 1 / (1 - rho) (rho: the ratio of the two steps' lengths), at most by this factor: the
  // iterations' geometric tail is skipped (realistic presets: 8-10 -> 7 iterations). 2.0 saved
  // half an iteration more on the legged tunnel but its APE rose by 3-4 mm on two of three
  // seeds; 1.5 kept it (README). 1: plain Gauss-Newton steps.
  double max_step_extrapolation = 1.5;
  // Coarse to fine: the first searches pair only every k-th source point (each pair then
  // weighs k points' information), until a step moves no point farther than
  // correspondence_reuse_distance or converges; then every point is paired. A scan with a weak
  // (full mode) or degenerate direction leaves the coarse phase after its first search. The
  // search and the normal equations are most of the registration's cost and the first steps
  // need only the direction: on the campus loop 3 cut the registration by 27-39 % (README).
  // 1: off.
  int coarse_stride = 3;
  int min_correspondences = 30;         // fewer: the scan is not registered
  double covariance_regularisation = 1e-6;  // relative to trace(H)/6, keeps H invertible
};

constexpr bool ClassWise(RegistrationMode m) {
  return m == RegistrationMode::kFull || m == RegistrationMode::kFullRemap ||
         m == RegistrationMode::kClassesNoDegeneracy;
}
constexpr bool UsesDegeneracyWeights(RegistrationMode m) {
  return m == RegistrationMode::kFullRemap;
}
constexpr bool UsesMotionPrior(RegistrationMode m) { return m == RegistrationMode::kFull; }

}  // namespace dammloam
