#include "io/config_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include "io/yaml_section.hpp"

namespace dammloam::io {

namespace {

void GetMode(Section& s, const std::string& key, RegistrationMode& mode) {
  std::string name(Name(mode));
  s.Get(key, name);
  const auto parsed = ParseRegistrationMode(name);
  if (!parsed) {
    s.Fail(key, "unknown value '" + name +
                      "' (expected full, point_to_point, plane_only or classes_no_degeneracy)");
  }
  mode = *parsed;
}

void ReadPreprocess(Section s, PreprocessConfig& c) {
  s.Get("min_range", c.min_range);
  s.Get("max_range", c.max_range);
  Section ri = s.Child("range_image");
  ri.Get("rows", c.range_image.rows);
  ri.Get("cols", c.range_image.cols);
  ri.Get("max_auto_cols", c.range_image.max_auto_cols);
  ri.Get("max_auto_pixels", c.range_image.max_auto_pixels);
  ri.Get("min_auto_cols", c.range_image.min_auto_cols);
  ri.Get("max_inherit_distance", c.range_image.max_inherit_distance);
  ri.RejectUnknownKeys();
  Section n = s.Child("normals");
  n.Get("min_incidence_deg", c.normals.min_incidence_deg);
  n.Get("range_noise", c.normals.range_noise);
  n.Get("min_tangent_sine", c.normals.min_tangent_sine);
  n.Get("min_baseline", c.normals.min_baseline);
  n.Get("max_stencil", c.normals.max_stencil);
  n.RejectUnknownKeys();
  Section k = s.Child("classifier");
  k.Get("majority", c.classifier.majority);
  k.Get("edge_angle_deg", c.classifier.edge_angle_deg);
  k.Get("min_valid_normals", c.classifier.min_valid_normals);
  k.Get("dominance", c.classifier.dominance);
  k.Get("require_centre_normal", c.classifier.require_centre_normal);
  k.RejectUnknownKeys();
  s.RejectUnknownKeys();
}

void ReadDownsample(Section s, DownsampleConfig& c) {
  s.Get("initial_voxel_unknown", c.initial_voxel_unknown);
  s.Get("initial_voxel_ground", c.initial_voxel_ground);
  s.Get("initial_voxel_roof", c.initial_voxel_roof);
  s.Get("initial_voxel_wall", c.initial_voxel_wall);
  s.Get("initial_voxel_edge", c.initial_voxel_edge);
  s.Get("target_points", c.target_points);
  s.Get("tolerance", c.tolerance);
  s.Get("min_voxel", c.min_voxel);
  s.Get("max_voxel", c.max_voxel);
  s.Get("max_step", c.max_step);
  s.RejectUnknownKeys();
}

void ReadMap(Section s, MapConfig& c) {
  s.Get("voxel_size", c.voxel_size);
  s.Get("auto_voxel_range_factor", c.auto_voxel_range_factor);
  s.Get("auto_voxel_min", c.auto_voxel_min);
  s.Get("auto_voxel_max", c.auto_voxel_max);
  s.Get("max_points_per_voxel", c.max_points_per_voxel);
  s.Get("max_distance", c.max_distance);
  s.RejectUnknownKeys();
}

void ReadRegistration(Section s, RegistrationConfig& c) {
  GetMode(s, "mode", c.mode);
  s.Get("max_iterations", c.max_iterations);
  s.Get("convergence_criterion", c.convergence_criterion);
  s.Get("initial_threshold", c.initial_threshold);
  s.Get("min_motion_threshold", c.min_motion_threshold);
  s.Get("degenerate_eigenvalue_ratio", c.degenerate_eigenvalue_ratio);
  s.Get("degenerate_release_ratio", c.degenerate_release_ratio);
  s.Get("remap_degenerate_directions", c.remap_degenerate_directions);
  s.Get("unknown_defers_to_map", c.unknown_defers_to_map);
  s.Get("weight_point_residuals", c.weight_point_residuals);
  s.Get("weight_always", c.weight_always);
  s.Get("strong_normal_cosine", c.strong_normal_cosine);
  s.Get("point_flatness", c.point_flatness);
  s.Get("judge_point_pairs_always", c.judge_point_pairs_always);
  s.Get("point_shape_min_points", c.point_shape_min_points);
  s.Get("line_normal_support", c.line_normal_support);
  s.Get("weak_eigenvalue_ratio", c.weak_eigenvalue_ratio);
  s.Get("residual_sigma", c.residual_sigma);
  s.Get("correspondence_reuse_distance", c.correspondence_reuse_distance);
  s.Get("max_step_extrapolation", c.max_step_extrapolation);
  s.Get("coarse_stride", c.coarse_stride);
  s.Get("min_correspondences", c.min_correspondences);
  s.Get("covariance_regularisation", c.covariance_regularisation);
  s.RejectUnknownKeys();
}

void ReadMotionPrior(Section s, OdometryConfig& c) {
  s.Get("acceleration", c.motion_prior.acceleration);
  s.Get("speed_change", c.motion_prior.speed_change);
  s.Get("max_speed_sigma", c.motion_prior.max_speed_sigma);
  s.Get("gait_time", c.motion_prior.gait_time);
  s.Get("degenerate_gate_sigmas", c.degenerate_gate_sigmas);
  s.Get("angular_acceleration", c.max_angular_acceleration);
  s.Get("in_scan_velocity_sigma", c.in_scan_velocity_sigma);
  s.Get("in_scan_rate_sigma", c.in_scan_rate_sigma);
  s.Get("in_scan_angular_acceleration_sigma", c.in_scan_angular_acceleration_sigma);
  s.Get("in_scan_spin_axis_acceleration_sigma", c.in_scan_spin_axis_acceleration_sigma);
  s.Retired("hold_spin_axis_acceleration",
            "in_scan_spin_axis_acceleration_sigma (0 holds it, as 'true' did)");
  s.RejectUnknownKeys();
}

void ReadMoving(Section s, OdometryConfig& c) {
  MovingPointsConfig& m = c.moving;
  s.Get("enabled", m.enabled);
  s.Get("margin", m.margin);
  s.Get("margin_per_metre", m.margin_per_metre);
  s.Get("max_range", m.max_range);
  s.Get("cluster_spacing", m.cluster_spacing);
  s.Get("min_evidence", m.min_evidence);
  s.Get("min_evidence_share", m.min_evidence_share);
  s.Get("max_object_extent", m.max_object_extent);
  s.Get("map_after", m.map_after);
  s.Get("map_after_max_gap", m.map_after_max_gap);
  s.Get("remove_moved_away_every", c.remove_moved_away_every);
  s.RejectUnknownKeys();
}

void ReadCompactObjects(Section s, CompactObjectsConfig& c) {
  s.Get("enabled", c.enabled);
  s.Get("cell", c.cell);
  s.Get("max_range", c.max_range);
  s.Get("max_extent", c.max_extent);
  s.Get("max_lift", c.max_lift);
  s.Get("max_height", c.max_height);
  s.Get("min_height", c.min_height);
  s.Get("facing_cos", c.facing_cos);
  s.Get("body_depth", c.body_depth);
  s.Get("body_margin", c.body_margin);
  s.Get("min_ground_points", c.min_ground_points);
  s.Get("ground_reach", c.ground_reach);
  s.Get("weak_axis_ratio", c.weak_axis_ratio);
  s.Get("witness_share", c.witness_share);
  s.Get("map_after", c.map_after);
  s.Get("top_margin_deg", c.top_margin_deg);
  s.RejectUnknownKeys();
}

void ReadAccelerometer(Section s, AccelUseConfig& c) {
  s.Get("enabled", c.enabled);
  s.Get("acceleration_sigma", c.acceleration_sigma);
  s.Get("deskew", c.deskew);
  s.Get("saturation", c.saturation);
  Section g = s.Child("gravity");
  g.Get("warmup", c.gravity.warmup);
  g.Get("initial_sigma", c.gravity.initial_sigma);
  g.Get("bias_sigma", c.gravity.bias_sigma);
  g.Get("velocity_sigma", c.gravity.velocity_sigma);
  g.Get("gravity_walk", c.gravity.gravity_walk);
  g.Get("bias_walk", c.gravity.bias_walk);
  g.Get("trusted_sigma", c.gravity.trusted_sigma);
  g.RejectUnknownKeys();
  s.RejectUnknownKeys();
}

void ReadHealth(Section s, TrackingHealthConfig& h) {
  s.Get("reference_scans", h.reference_scans);
  s.Get("degraded_pair_share", h.degraded_pair_share);
  s.Get("lost_pair_share", h.lost_pair_share);
  s.Get("max_innovation_gates", h.max_innovation_gates);
  s.Get("restart_after_lost_scans", h.restart_after_lost_scans);
  s.Get("max_turn_rate_deg_s", h.max_turn_rate_deg_s);
  s.Get("search_after_turn_deg", h.search_after_turn_deg);
  s.RejectUnknownKeys();
}

void Require(bool ok, const char* field, const std::string& what) {
  if (!ok) throw ConfigError(std::string(field) + ": " + what);
}

}  // namespace

OdometryConfig ParseOdometryConfig(const YAML::Node& root) {
  OdometryConfig config;
  Section s(root, "");
  ReadPreprocess(s.Child("preprocess"), config.preprocess);
  ReadDownsample(s.Child("downsample"), config.downsample);
  ReadMap(s.Child("map"), config.map);
  ReadRegistration(s.Child("registration"), config.registration);
  ReadMotionPrior(s.Child("motion_prior"), config);
  ReadMoving(s.Child("moving"), config);
  ReadCompactObjects(s.Child("compact_objects"), config.compact_objects);
  ReadAccelerometer(s.Child("accelerometer"), config.accelerometer);
  ReadHealth(s.Child("health"), config.health);
  s.Get("map_frame_voxel_factor", config.map_frame_voxel_factor);
  s.Get("deskew", config.deskew);
  s.Get("interpolate_start_pose", config.interpolate_start_pose);
  s.Get("min_points", config.min_points);
  s.Get("max_time_gap", config.max_time_gap);
  s.Get("motion_model_max_deviation", config.motion_model_max_deviation);
  s.Get("threshold_range_factor", config.threshold_range_factor);
  s.RejectUnknownKeys();
  ValidateOdometryConfig(config);
  return config;
}

OdometryConfig LoadOdometryConfig(const std::filesystem::path& file) {
  const YAML::Node root = LoadYamlFile(file);
  try {
    return ParseOdometryConfig(root);
  } catch (const ConfigError& e) {
    throw ConfigError(file.string() + ": " + e.what());
  }
}

void ValidateOdometryConfig(const OdometryConfig& c) {
  const auto& p = c.preprocess;
  Require(p.min_range >= 0.0, "preprocess.min_range", "must be >= 0");
  Require(p.max_range > p.min_range, "preprocess.max_range", "must exceed min_range");
  Require(p.range_image.rows >= 0, "preprocess.range_image.rows", "must be >= 0");
  Require(p.range_image.cols >= 0, "preprocess.range_image.cols", "must be >= 0");
  Require(p.range_image.max_auto_cols >= 0, "preprocess.range_image.max_auto_cols",
          "must be >= 0");
  Require(p.range_image.max_auto_pixels >= 0, "preprocess.range_image.max_auto_pixels",
          "must be >= 0");
  Require(p.range_image.min_auto_cols >= 1, "preprocess.range_image.min_auto_cols",
          "must be >= 1");
  Require(p.range_image.max_inherit_distance >= 0.0, "preprocess.range_image.max_inherit_distance",
          "must be >= 0");
  Require(p.normals.min_incidence_deg > 0.0 && p.normals.min_incidence_deg < 90.0,
          "preprocess.normals.min_incidence_deg", "must be in (0, 90)");
  Require(p.normals.range_noise >= 0.0, "preprocess.normals.range_noise", "must be >= 0");
  Require(p.normals.min_tangent_sine >= 0.0 && p.normals.min_tangent_sine < 1.0,
          "preprocess.normals.min_tangent_sine", "must be in [0, 1)");
  Require(p.normals.min_baseline >= 0.0, "preprocess.normals.min_baseline", "must be >= 0");
  Require(p.normals.max_stencil >= 1 && p.normals.max_stencil <= 128,
          "preprocess.normals.max_stencil", "must be in [1, 128]");
  Require(p.classifier.majority > 0.0 && p.classifier.majority <= 1.0,
          "preprocess.classifier.majority", "must be in (0, 1]");
  Require(p.classifier.edge_angle_deg > 0.0 && p.classifier.edge_angle_deg < 180.0,
          "preprocess.classifier.edge_angle_deg", "must be in (0, 180)");
  Require(p.classifier.min_valid_normals >= 1 && p.classifier.min_valid_normals <= 9,
          "preprocess.classifier.min_valid_normals", "must be in [1, 9]");
  Require(p.classifier.dominance >= 1.0, "preprocess.classifier.dominance", "must be >= 1");
  const auto& d = c.downsample;
  for (const auto& [value, name] :
       {std::pair{d.initial_voxel_unknown, "downsample.initial_voxel_unknown"},
        std::pair{d.initial_voxel_ground, "downsample.initial_voxel_ground"},
        std::pair{d.initial_voxel_roof, "downsample.initial_voxel_roof"},
        std::pair{d.initial_voxel_wall, "downsample.initial_voxel_wall"},
        std::pair{d.initial_voxel_edge, "downsample.initial_voxel_edge"}}) {
    Require(value > 0.0, name, "must be > 0");
  }
  Require(d.target_points > 0, "downsample.target_points", "must be > 0");
  Require(d.tolerance >= 0.0 && d.tolerance < 1.0, "downsample.tolerance", "must be in [0, 1)");
  Require(d.min_voxel > 0.0, "downsample.min_voxel", "must be > 0");
  Require(d.max_voxel >= d.min_voxel, "downsample.max_voxel", "must be >= min_voxel");
  Require(d.max_step > 1.0, "downsample.max_step", "must be > 1");
  const auto& m = c.map;
  Require(m.voxel_size >= 0.0, "map.voxel_size", "must be >= 0 (0 = automatic)");
  Require(m.auto_voxel_range_factor > 0.0, "map.auto_voxel_range_factor", "must be > 0");
  Require(m.auto_voxel_min > 0.0, "map.auto_voxel_min", "must be > 0");
  Require(m.auto_voxel_max >= m.auto_voxel_min, "map.auto_voxel_max", "must be >= auto_voxel_min");
  Require(m.max_points_per_voxel >= 1 && m.max_points_per_voxel <= kMaxPointsPerVoxel,
          "map.max_points_per_voxel", "must be in [1, 1000]");
  Require(m.max_distance > 0.0, "map.max_distance", "must be > 0");
  const auto& r = c.registration;
  Require(r.max_iterations >= 1, "registration.max_iterations", "must be >= 1");
  Require(r.correspondence_reuse_distance >= 0.0, "registration.correspondence_reuse_distance",
          "must be >= 0 (0 = search on every iteration)");
  Require(r.max_step_extrapolation >= 1.0 && r.max_step_extrapolation <= 10.0,
          "registration.max_step_extrapolation", "must be in [1, 10] (1 = off)");
  Require(r.coarse_stride >= 1 && r.coarse_stride <= 64, "registration.coarse_stride",
          "must be in [1, 64] (1 = off)");
  Require(r.convergence_criterion > 0.0, "registration.convergence_criterion", "must be > 0");
  Require(r.initial_threshold > 0.0, "registration.initial_threshold", "must be > 0");
  Require(r.min_motion_threshold >= 0.0, "registration.min_motion_threshold", "must be >= 0");
  Require(r.degenerate_eigenvalue_ratio >= 0.0 && r.degenerate_eigenvalue_ratio < 1.0,
          "registration.degenerate_eigenvalue_ratio", "must be in [0, 1)");
  Require(r.degenerate_release_ratio >= r.degenerate_eigenvalue_ratio &&
              r.degenerate_release_ratio < 1.0,
          "registration.degenerate_release_ratio", "must be in [degenerate_eigenvalue_ratio, 1)");
  Require(r.min_correspondences >= 6, "registration.min_correspondences", "must be >= 6");
  Require(r.covariance_regularisation >= 0.0, "registration.covariance_regularisation",
          "must be >= 0");
  Require(r.strong_normal_cosine >= 0.0 && r.strong_normal_cosine <= 1.0,
          "registration.strong_normal_cosine", "must be in [0, 1]");
  Require(r.point_flatness >= 0.0 && r.point_flatness <= 1.0 / 3.0,
          "registration.point_flatness", "must be in [0, 1/3]");
  Require(r.point_shape_min_points >= 3, "registration.point_shape_min_points",
          "must be >= 3 (a plane needs three points)");
  Require(r.line_normal_support >= 0.0 && r.line_normal_support <= 1.0,
          "registration.line_normal_support", "must be in [0, 1]");
  Require(r.weak_eigenvalue_ratio >= 0.0 && r.weak_eigenvalue_ratio < 1.0,
          "registration.weak_eigenvalue_ratio", "must be in [0, 1)");
  Require(r.residual_sigma > 0.0, "registration.residual_sigma", "must be > 0");
  const TrackingHealthConfig& h = c.health;
  Require(h.reference_scans >= 3, "health.reference_scans", "must be >= 3");
  Require(h.lost_pair_share >= 0.0 && h.lost_pair_share <= h.degraded_pair_share &&
              h.degraded_pair_share <= 1.0,
          "health.lost_pair_share", "must satisfy 0 <= lost_pair_share <= degraded_pair_share <= 1");
  Require(h.max_turn_rate_deg_s >= 0.0, "health.max_turn_rate_deg_s", "must be >= 0");
  Require(h.search_after_turn_deg > 0.0, "health.search_after_turn_deg", "must be > 0");
  Require(h.max_innovation_gates > 0.0, "health.max_innovation_gates", "must be > 0");
  Require(h.restart_after_lost_scans >= 0, "health.restart_after_lost_scans",
          "must be >= 0 (0: never start the map over)");
  const auto& mp = c.motion_prior;
  Require(mp.acceleration > 0.0, "motion_prior.acceleration", "must be > 0");
  Require(mp.speed_change > 0.0, "motion_prior.speed_change", "must be > 0");
  Require(mp.max_speed_sigma > 0.0, "motion_prior.max_speed_sigma", "must be > 0");
  Require(mp.gait_time > 0.0, "motion_prior.gait_time", "must be > 0");
  Require(c.degenerate_gate_sigmas >= 0.0, "motion_prior.degenerate_gate_sigmas", "must be >= 0");
  Require(c.max_angular_acceleration > 0.0, "motion_prior.angular_acceleration", "must be > 0");
  Require(c.in_scan_velocity_sigma >= 0.0, "motion_prior.in_scan_velocity_sigma", "must be >= 0");
  Require(c.in_scan_rate_sigma >= 0.0, "motion_prior.in_scan_rate_sigma", "must be >= 0");
  Require(c.in_scan_angular_acceleration_sigma >= 0.0,
          "motion_prior.in_scan_angular_acceleration_sigma", "must be >= 0");
  Require(c.in_scan_spin_axis_acceleration_sigma >= 0.0,
          "motion_prior.in_scan_spin_axis_acceleration_sigma", "must be >= 0");
  Require((c.in_scan_velocity_sigma > 0.0) == (c.in_scan_rate_sigma > 0.0),
          "motion_prior.in_scan_velocity_sigma",
          "and in_scan_rate_sigma must both be > 0 (in-scan motion on) or both 0 (off)");
  Require(c.in_scan_angular_acceleration_sigma == 0.0 || c.in_scan_rate_sigma > 0.0,
          "motion_prior.in_scan_angular_acceleration_sigma",
          "needs the in-scan motion on (in_scan_velocity_sigma and in_scan_rate_sigma > 0)");
  Require(c.map_frame_voxel_factor > 0.0, "map_frame_voxel_factor", "must be > 0");
  const MovingPointsConfig& mv = c.moving;
  Require(mv.margin > 0.0, "moving.margin", "must be > 0");
  Require(mv.margin_per_metre >= 0.0, "moving.margin_per_metre", "must be >= 0");
  Require(mv.max_range > 0.0, "moving.max_range", "must be > 0");
  Require(mv.cluster_spacing > 0.0, "moving.cluster_spacing", "must be > 0");
  Require(mv.min_evidence >= 1, "moving.min_evidence", "must be >= 1");
  Require(mv.min_evidence_share >= 0.0 && mv.min_evidence_share <= 1.0, "moving.min_evidence_share",
          "must be in [0, 1]");
  Require(mv.max_object_extent > 0.0, "moving.max_object_extent", "must be > 0");
  Require(mv.map_after >= 0.0, "moving.map_after", "must be >= 0");
  Require(mv.map_after_max_gap > 0.0, "moving.map_after_max_gap", "must be > 0");
  Require(c.remove_moved_away_every >= 1, "moving.remove_moved_away_every", "must be >= 1");
  const CompactObjectsConfig& co = c.compact_objects;
  Require(co.cell > 0.0, "compact_objects.cell", "must be > 0");
  Require(co.max_range > 0.0 && co.max_range <= 200.0, "compact_objects.max_range",
          "must be in (0, 200] m (the grid is max_range / cell cells across)");
  Require(co.max_range / co.cell <= 2000.0, "compact_objects.cell",
          "too fine for max_range (more than 2000 cells each way)");
  Require(co.max_extent > 0.0, "compact_objects.max_extent", "must be > 0");
  Require(co.max_lift >= 0.0, "compact_objects.max_lift", "must be >= 0");
  Require(co.max_height > 0.0, "compact_objects.max_height", "must be > 0");
  Require(co.min_height >= 0.0 && co.min_height < co.max_height, "compact_objects.min_height",
          "must be in [0, max_height)");
  Require(co.facing_cos >= 0.0 && co.facing_cos <= 1.0, "compact_objects.facing_cos", "must be in [0, 1]");
  Require(co.body_depth >= 0.0, "compact_objects.body_depth", "must be >= 0");
  Require(co.body_margin >= 0.0, "compact_objects.body_margin", "must be >= 0");
  Require(co.min_ground_points >= 1, "compact_objects.min_ground_points", "must be >= 1");
  Require(co.ground_reach > 0.0, "compact_objects.ground_reach", "must be > 0");
  Require(co.weak_axis_ratio >= 0.0 && co.weak_axis_ratio <= 1.0, "compact_objects.weak_axis_ratio",
          "must be in [0, 1]");
  Require(co.witness_share >= 0.0, "compact_objects.witness_share", "must be >= 0");
  Require(co.map_after >= 0.0 && std::isfinite(co.map_after), "compact_objects.map_after",
          "must be a finite number of seconds >= 0");
  const AccelUseConfig& ac = c.accelerometer;
  Require(ac.acceleration_sigma > 0.0 && std::isfinite(ac.acceleration_sigma),
          "accelerometer.acceleration_sigma", "must be > 0");
  Require(ac.saturation > 0.0, "accelerometer.saturation", "must be > 0");
  Require(ac.gravity.warmup >= 0.0, "accelerometer.gravity.warmup", "must be >= 0");
  Require(ac.gravity.initial_sigma > 0.0, "accelerometer.gravity.initial_sigma", "must be > 0");
  Require(ac.gravity.velocity_sigma > 0.0, "accelerometer.gravity.velocity_sigma", "must be > 0");
  Require(ac.gravity.bias_sigma > 0.0, "accelerometer.gravity.bias_sigma", "must be > 0");
  Require(ac.gravity.gravity_walk >= 0.0, "accelerometer.gravity.gravity_walk", "must be >= 0");
  Require(ac.gravity.bias_walk >= 0.0, "accelerometer.gravity.bias_walk", "must be >= 0");
  Require(ac.gravity.trusted_sigma > 0.0, "accelerometer.gravity.trusted_sigma", "must be > 0");
  Require(co.top_margin_deg >= 0.0 && co.top_margin_deg <= 90.0, "compact_objects.top_margin_deg",
          "must be in [0, 90] degrees");
  Require(c.min_points >= 1, "min_points", "must be >= 1");
  Require(c.max_time_gap > 0.0, "max_time_gap", "must be > 0");
  Require(c.motion_model_max_deviation >= 0.0, "motion_model_max_deviation", "must be >= 0");
  Require(c.threshold_range_factor >= 0.0, "threshold_range_factor", "must be >= 0");
}

}  // namespace dammloam::io
