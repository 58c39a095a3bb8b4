#pragma once

#include "core/inertial/accel_use_config.hpp"
#include "core/map/map_config.hpp"
#include "core/odometry/compact_objects.hpp"
#include "core/odometry/moving_points.hpp"
#include "core/odometry/tracking_health.hpp"
#include "core/odometry/translation_filter.hpp"
#include "core/preprocess/preprocess_config.hpp"
#include "core/registration/registration_config.hpp"

namespace dammloam {

// Everything the odometry front end can be told; plain values with defaults that serve
// OS1-64 and VLP-16, indoors and outdoors (the paper's "consistent parameters").
struct OdometryConfig {
  PreprocessConfig preprocess;
  DownsampleConfig downsample;  // registration source (class-aware, adaptive)
  MapConfig map;
  RegistrationConfig registration;
  // Full mode's motion prior: how far the carrier departs from constant velocity. The
  // defaults fit a hand-held sensor and serve wheeled and legged carriers too.
  TranslationFilter::Config motion_prior;
  // Points on things that move (people, vehicles, doors) are kept out of registration and out
  // of the map, and map points that have since moved away are removed.
  MovingPointsConfig moving;
  int remove_moved_away_every = 5;  // scans between two passes of that removal
  // Small things standing on the ground (people, carts) never hold a direction the rest of the
  // scan does not observe: where they would, they stay out of registration and map.
  CompactObjectsConfig compact_objects;
  // With an IMU (EnableImu): the accelerometer's velocity change in the motion prior.
  AccelUseConfig accelerometer;
  double max_angular_acceleration = 5.0;  // rad/s^2: orientation prior sigma = this * dt^2
  // Between sparse scans (not consecutive at the sensor's rate), along a degenerate direction
  // a registration that lands farther from the prediction than this many of the prior's
  // sigmas keeps the predicted position there (the scan is then degraded); 0: never. Full
  // mode only.
  double degenerate_gate_sigmas = 3.0;
  // In-scan motion. The deskew velocity is one scan old: a hand's 4-9 Hz shake turns the
  // sensor at up to ~0.3 rad/s and reverses within a scan, a trot pitches at 2.5-3 Hz, a
  // walker's bob changes the vertical speed by ~0.4 m/s per scan; the deskew then bends walls
  // and floor by centimetres and no rigid pose fits them. Both sigmas > 0: full mode estimates
  // how the scan's own linear (m/s) and angular (rad/s) velocity depart from the deskew
  // velocity, with the pose, and deskews the scan again with it before it enters the map.
  // 0: off. The sigmas act as a regulariser rather than as the physical spread: the scan's
  // data outweighs them either way, and at the physical scale (0.05 m/s, 0.3 rad/s) errors
  // the data shares (map, ring pattern) bent the wheeled VLP-16 zigzag's scans (APE 0.028 ->
  // 0.032), while 0.01 keeps every preset's gain (see README).
  double in_scan_velocity_sigma = 0.01;
  double in_scan_rate_sigma = 0.01;
  // With both above > 0: the scan's angular acceleration too (1 sigma, rad/s^2; 0: off). A
  // hand's 4-9 Hz shake of 0.3 deg reverses its turn within a 0.1 s scan; the even part of
  // that turn (the scan's two ends tilted one way against its middle) shifts the floor and
  // ceiling ahead and behind the same way, like a change of height, which a constant in-scan
  // rate cannot take up. Like the two above, a regulariser: the shake's physical scale is
  // 5-10 rad/s^2, but at 1 the VLP-16's few floor and ceiling pairs let it trade with the
  // height and the wheeled zigzag drifted (APE 0.023 -> 0.037); 0.3 keeps most of the gain on
  // the hand-held and legged runs (README).
  double in_scan_angular_acceleration_sigma = 0.3;
  // About the sensor's spin axis that acceleration has its own sigma (rad/s^2; 0 holds it, as
  // the previous release did), and it is held there while a direction is weak. A hand's yaw
  // shake warps the scan's azimuths: outdoors, where every direction is observed, estimating
  // the warp cut the campus APE from 0.021 to 0.015 m. Estimated in weak scans too, it helped
  // the corridors by a few millimetres but let the estimate run away along the featureless
  // endless corridor on two of four runs (README).
  double in_scan_spin_axis_acceleration_sigma = 0.1;
  // Map insertion keeps one point per class per voxel of this fraction of the map voxel.
  double map_frame_voxel_factor = 0.5;
  // The adaptive threshold turns a rotation deviation into a displacement at this multiple of
  // the first scan's median range (at most map.max_distance); 0: at map.max_distance, as
  // KISS-ICP does with the sensor's range. In a hand-held VLP-16 corridor (median range 1.9 m)
  // 100 m made the gate 4.7 m wide under 0.5 deg of shake, and single scans slid 0.2 m along
  // the axis (worst frame 0.236 m; 0.151 m at 4).
  double threshold_range_factor = 4.0;
  bool deskew = true;
  // The reported scan-start pose: interpolated between the previous and this scan's mid-scan
  // poses (both registered), or extrapolated back from this mid-scan pose with the velocity
  // the scan was deskewed with. That velocity is one scan old; under a hand's shake and a
  // walker's bob it is off by ~0.4 m/s, i.e. 2 cm at the scan start.
  bool interpolate_start_pose = true;
  int min_points = 100;        // valid points a scan needs to be registered
  double max_time_gap = 1.0;   // seconds; a longer gap resets the constant-velocity model
  // Metres. The constant-velocity model "holds" while registrations land within this of its
  // prediction; only then does registration keep the prediction along degenerate directions.
  // A registration farther off while the model has not held (start while moving, after a
  // reset) is deskewed again with the motion it measured and refined once more.
  double motion_model_max_deviation = 0.1;
  TrackingHealthConfig health;
};

}  // namespace dammloam
