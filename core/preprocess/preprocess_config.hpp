#pragma once
#include <cstddef>

// Settings of the feature stage (paper Sec. III-A) and of the class-aware downsampler.
// The defaults are chosen to serve both a dense OS1-64 and a sparse VLP-16, indoors and
// outdoors: thresholds are angles or ratios, never sensor-specific distances.
namespace dammloam {

struct RangeImageConfig {
  int rows = 0;  // 0: SensorModel::rings (or the largest ring index + 1 if more)
  int cols = 0;  // 0: SensorModel::columns, within max_auto_cols and max_auto_pixels
  // Coarser pixels than the sensor's: a point that shares its pixel inherits the nearer one's
  // label and normal, and tangents widen to their 0.2 m baseline anyway (see NormalMap).
  int max_auto_cols = 0;  // 0: no cap
  // The feature stage costs per pixel, and a dense sensor has pixels to spare: the automatic
  // column count is cut until rows x cols fits this budget, but not below min_auto_cols. An
  // OS1-64 x 1024 gets 512 columns (0.7 x 0.53 deg pixels): normals and classification halve,
  // and on 9 full-length OS1-64 runs APE and RPE stayed within a millimetre or improved
  // (README). A VLP-16 x 1800 (28,800 pixels) keeps its grid: its 16 rings leave nothing to
  // spare, and at 512 columns its wheeled corridor lost 1 cm (APE 0.022 -> 0.033 m).
  int max_auto_pixels = 32768;  // 0: no budget
  int min_auto_cols = 512;
  // A point that lost its pixel to a nearer one inherits the winner's label and normal when it
  // lies within this distance of it (same surface); otherwise it stays Unknown.
  double max_inherit_distance = 0.2;  // metres
};

struct NormalMapConfig {
  // Depth discontinuity test between neighbouring pixels. A plane seen at incidence angle beta
  // changes range by about r * delta * cot(beta) between rays delta radians apart, so a jump
  // larger than that for beta = min_incidence_deg is taken as a different surface. Scaling with
  // the actual ray separation makes one threshold serve 0.35 deg and 2 deg beam spacings.
  double min_incidence_deg = 2.0;
  double range_noise = 0.03;  // metres, added to the allowed jump (sensor noise near the sensor)
  // |t_u x t_v| below this fraction of |t_u| |t_v| (sine of the tangent angle): degenerate.
  double min_tangent_sine = 0.05;
  // Tangents widen their stencil up to max_stencil pixels each side until they span
  // 2 * min_baseline metres, so range noise cannot dominate the normal (see normal_map.cpp).
  double min_baseline = 0.1;  // metres
  // Wide enough for the baseline at 0.2 deg columns (VLP-16 at 10 Hz) on a wall 1 m away;
  // the walk strides, so the width costs about two steps whatever it is.
  int max_stencil = 32;
};

struct ClassifierConfig {
  double majority = 2.0 / 3.0;   // share of valid 3x3 normals voting for ground/roof/wall
  double edge_angle_deg = 15.0;  // mean pairwise normal angle above which a pixel is an edge
  int min_valid_normals = 4;     // of the 9 in the window; fewer -> Unknown
  // A normal "has a dominant component k" when |n_k| >= dominance * every other |n_j|.
  // 1.0 is the paper's rule (the largest component wins).
  double dominance = 1.0;
  // Ground/roof/wall also need the centre pixel's own normal: planar residuals use it.
  bool require_centre_normal = true;
};

struct DownsampleConfig {
  // Initial voxel sizes in metres, indexed by PointClass (unknown, ground, roof, wall, edge).
  // Edges are rare and constrain rotation best, so they keep the finest grid.
  double initial_voxel_unknown = 2.0;
  double initial_voxel_ground = 0.8;
  double initial_voxel_roof = 0.8;
  double initial_voxel_wall = 0.5;
  double initial_voxel_edge = 2.0;
  std::size_t target_points = 6000;  // kept points per scan the adaptation aims for
  double tolerance = 0.05;           // relative band around the target with no update
  double min_voxel = 0.05;           // metres, clamp of every class's voxel size
  double max_voxel = 3.0;
  double max_step = 2.0;  // largest change factor of the voxel sizes per scan
};

struct PreprocessConfig {
  RangeImageConfig range_image;
  NormalMapConfig normals;
  ClassifierConfig classifier;
  // Valid range; the effective interval is intersected with the SensorModel's.
  double min_range = 0.3;
  double max_range = 120.0;
};

}  // namespace dammloam
