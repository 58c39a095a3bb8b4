#pragma once

namespace dammloam {

// Local map parameters. One default serves indoors and outdoors: with voxel_size = 0 the map
// voxel is derived from the first scan's median range (see AutoVoxelSize), so a 2 m wide
// corridor gets a fine map and an open street a coarse one.
struct MapConfig {
  double voxel_size = 0.0;              // metres; 0 = derive from the first scan
  double auto_voxel_range_factor = 0.05;  // voxel = factor * median range of the first scan
  double auto_voxel_min = 0.25;         // metres, clamp of the derived voxel size
  double auto_voxel_max = 1.0;
  // Per class: a busy class cannot crowd out another. Few, so that the first sightings of a
  // surface anchor it: with 20, a far end wall seen by a handful of points per scan became a
  // slab as thick as the drift while it was seen, and matching inside the slab told the axis
  // nothing (hand-held VLP-16 corridor: 1.15 m APE, 0.05 m with 3).
  int max_points_per_voxel = 3;
  double max_distance = 100.0;          // metres; voxels farther from the sensor are dropped
};

// Per class and voxel; the map indexes a voxel's points with 16 bits.
inline constexpr int kMaxPointsPerVoxel = 1000;

// The map voxel size used for a sequence whose first scan has this median range.
double AutoVoxelSize(const MapConfig& config, double median_range);

}  // namespace dammloam
