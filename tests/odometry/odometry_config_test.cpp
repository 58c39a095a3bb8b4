#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "io/config_yaml.hpp"

namespace dammloam {
namespace {

std::string ErrorOf(const std::string& yaml) {
  try {
    io::ParseOdometryConfig(YAML::Load(yaml));
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

// Every key, compared exactly: the file is what users start from, so it must give the same
// poses as no file. A rounded 2/3 for the classifier's majority (0.6666667) once made six of
// nine votes fall short, which a tolerance of 1e-6 here did not see.
TEST(OdometryConfigYaml, ShippedDefaultFileLoadsAndEqualsTheDefaults) {
  const auto file = std::filesystem::path(DAMMLOAM_SOURCE_DIR) / "deploy/config/odometry.yaml";
  const OdometryConfig a = io::LoadOdometryConfig(file);
  const OdometryConfig b;
#define DAMMLOAM_EXPECT_SAME(field) EXPECT_EQ(a.field, b.field) << #field
  DAMMLOAM_EXPECT_SAME(preprocess.min_range);
  DAMMLOAM_EXPECT_SAME(preprocess.max_range);
  DAMMLOAM_EXPECT_SAME(preprocess.range_image.rows);
  DAMMLOAM_EXPECT_SAME(preprocess.range_image.cols);
  DAMMLOAM_EXPECT_SAME(preprocess.range_image.max_auto_cols);
  DAMMLOAM_EXPECT_SAME(preprocess.range_image.max_auto_pixels);
  DAMMLOAM_EXPECT_SAME(preprocess.range_image.min_auto_cols);
  DAMMLOAM_EXPECT_SAME(preprocess.range_image.max_inherit_distance);
  DAMMLOAM_EXPECT_SAME(preprocess.normals.min_incidence_deg);
  DAMMLOAM_EXPECT_SAME(preprocess.normals.range_noise);
  DAMMLOAM_EXPECT_SAME(preprocess.normals.min_tangent_sine);
  DAMMLOAM_EXPECT_SAME(preprocess.normals.min_baseline);
  DAMMLOAM_EXPECT_SAME(preprocess.normals.max_stencil);
  DAMMLOAM_EXPECT_SAME(preprocess.classifier.majority);
  DAMMLOAM_EXPECT_SAME(preprocess.classifier.edge_angle_deg);
  DAMMLOAM_EXPECT_SAME(preprocess.classifier.min_valid_normals);
  DAMMLOAM_EXPECT_SAME(preprocess.classifier.dominance);
  DAMMLOAM_EXPECT_SAME(preprocess.classifier.require_centre_normal);
  DAMMLOAM_EXPECT_SAME(downsample.initial_voxel_unknown);
  DAMMLOAM_EXPECT_SAME(downsample.initial_voxel_ground);
  DAMMLOAM_EXPECT_SAME(downsample.initial_voxel_roof);
  DAMMLOAM_EXPECT_SAME(downsample.initial_voxel_wall);
  DAMMLOAM_EXPECT_SAME(downsample.initial_voxel_edge);
  DAMMLOAM_EXPECT_SAME(downsample.target_points);
  DAMMLOAM_EXPECT_SAME(downsample.tolerance);
  DAMMLOAM_EXPECT_SAME(downsample.min_voxel);
  DAMMLOAM_EXPECT_SAME(downsample.max_voxel);
  DAMMLOAM_EXPECT_SAME(downsample.max_step);
  DAMMLOAM_EXPECT_SAME(map.voxel_size);
  DAMMLOAM_EXPECT_SAME(map.auto_voxel_range_factor);
  DAMMLOAM_EXPECT_SAME(map.auto_voxel_min);
  DAMMLOAM_EXPECT_SAME(map.auto_voxel_max);
  DAMMLOAM_EXPECT_SAME(map.max_points_per_voxel);
  DAMMLOAM_EXPECT_SAME(map.max_distance);
  DAMMLOAM_EXPECT_SAME(registration.mode);
  DAMMLOAM_EXPECT_SAME(registration.max_iterations);
  DAMMLOAM_EXPECT_SAME(registration.convergence_criterion);
  DAMMLOAM_EXPECT_SAME(registration.initial_threshold);
  DAMMLOAM_EXPECT_SAME(registration.min_motion_threshold);
  DAMMLOAM_EXPECT_SAME(registration.degenerate_eigenvalue_ratio);
  DAMMLOAM_EXPECT_SAME(registration.degenerate_release_ratio);
  DAMMLOAM_EXPECT_SAME(registration.remap_degenerate_directions);
  DAMMLOAM_EXPECT_SAME(registration.weight_always);
  DAMMLOAM_EXPECT_SAME(registration.weight_point_residuals);
  DAMMLOAM_EXPECT_SAME(registration.unknown_defers_to_map);
  DAMMLOAM_EXPECT_SAME(registration.strong_normal_cosine);
  DAMMLOAM_EXPECT_SAME(registration.point_flatness);
  DAMMLOAM_EXPECT_SAME(registration.judge_point_pairs_always);
  DAMMLOAM_EXPECT_SAME(registration.point_shape_min_points);
  DAMMLOAM_EXPECT_SAME(registration.line_normal_support);
  DAMMLOAM_EXPECT_SAME(registration.weak_eigenvalue_ratio);
  DAMMLOAM_EXPECT_SAME(registration.residual_sigma);
  DAMMLOAM_EXPECT_SAME(registration.correspondence_reuse_distance);
  DAMMLOAM_EXPECT_SAME(registration.max_step_extrapolation);
  DAMMLOAM_EXPECT_SAME(registration.coarse_stride);
  DAMMLOAM_EXPECT_SAME(registration.min_correspondences);
  DAMMLOAM_EXPECT_SAME(registration.covariance_regularisation);
  DAMMLOAM_EXPECT_SAME(motion_prior.acceleration);
  DAMMLOAM_EXPECT_SAME(motion_prior.speed_change);
  DAMMLOAM_EXPECT_SAME(motion_prior.gait_time);
  DAMMLOAM_EXPECT_SAME(degenerate_gate_sigmas);
  DAMMLOAM_EXPECT_SAME(motion_prior.max_speed_sigma);
  DAMMLOAM_EXPECT_SAME(max_angular_acceleration);
  DAMMLOAM_EXPECT_SAME(in_scan_velocity_sigma);
  DAMMLOAM_EXPECT_SAME(in_scan_rate_sigma);
  DAMMLOAM_EXPECT_SAME(in_scan_angular_acceleration_sigma);
  DAMMLOAM_EXPECT_SAME(in_scan_spin_axis_acceleration_sigma);
  DAMMLOAM_EXPECT_SAME(map_frame_voxel_factor);
  DAMMLOAM_EXPECT_SAME(threshold_range_factor);
  DAMMLOAM_EXPECT_SAME(deskew);
  DAMMLOAM_EXPECT_SAME(interpolate_start_pose);
  DAMMLOAM_EXPECT_SAME(min_points);
  DAMMLOAM_EXPECT_SAME(max_time_gap);
  DAMMLOAM_EXPECT_SAME(motion_model_max_deviation);
  DAMMLOAM_EXPECT_SAME(accelerometer.enabled);
  DAMMLOAM_EXPECT_SAME(accelerometer.acceleration_sigma);
  DAMMLOAM_EXPECT_SAME(accelerometer.saturation);
  DAMMLOAM_EXPECT_SAME(accelerometer.deskew);
  DAMMLOAM_EXPECT_SAME(accelerometer.gravity.warmup);
  DAMMLOAM_EXPECT_SAME(accelerometer.gravity.initial_sigma);
  DAMMLOAM_EXPECT_SAME(accelerometer.gravity.gravity_walk);
  DAMMLOAM_EXPECT_SAME(accelerometer.gravity.bias_walk);
  DAMMLOAM_EXPECT_SAME(accelerometer.gravity.trusted_sigma);
  DAMMLOAM_EXPECT_SAME(accelerometer.gravity.velocity_sigma);
  DAMMLOAM_EXPECT_SAME(accelerometer.gravity.bias_sigma);
  DAMMLOAM_EXPECT_SAME(health.reference_scans);
  DAMMLOAM_EXPECT_SAME(health.degraded_pair_share);
  DAMMLOAM_EXPECT_SAME(health.lost_pair_share);
  DAMMLOAM_EXPECT_SAME(health.max_innovation_gates);
  DAMMLOAM_EXPECT_SAME(health.restart_after_lost_scans);
  DAMMLOAM_EXPECT_SAME(health.max_turn_rate_deg_s);
  DAMMLOAM_EXPECT_SAME(health.search_after_turn_deg);
#undef DAMMLOAM_EXPECT_SAME
}

TEST(OdometryConfigYaml, ValuesAreRead) {
  const OdometryConfig c = io::ParseOdometryConfig(YAML::Load(
      "registration: {mode: plane_only, max_iterations: 7, max_step_extrapolation: 1.0,\n"
      "               point_shape_min_points: 12, line_normal_support: 0.25, coarse_stride: 1}\n"
      "map: {voxel_size: 0.4}\n"
      "preprocess: {classifier: {edge_angle_deg: 20}}\ndeskew: false\n"
      "health: {lost_pair_share: 0.2, restart_after_lost_scans: 0}\n"
      "motion_prior: {in_scan_velocity_sigma: 0, in_scan_rate_sigma: 0,\n"
      "               in_scan_angular_acceleration_sigma: 0,\n"
      "               in_scan_spin_axis_acceleration_sigma: 0}\n"));
  EXPECT_EQ(c.registration.mode, RegistrationMode::kPlaneOnly);
  EXPECT_EQ(c.registration.max_iterations, 7);
  EXPECT_DOUBLE_EQ(c.map.voxel_size, 0.4);
  EXPECT_DOUBLE_EQ(c.preprocess.classifier.edge_angle_deg, 20.0);
  EXPECT_FALSE(c.deskew);
  EXPECT_DOUBLE_EQ(c.health.lost_pair_share, 0.2);
  EXPECT_EQ(c.health.restart_after_lost_scans, 0);
  EXPECT_DOUBLE_EQ(c.registration.max_step_extrapolation, 1.0);
  EXPECT_EQ(c.registration.point_shape_min_points, 12);
  EXPECT_DOUBLE_EQ(c.registration.line_normal_support, 0.25);
  EXPECT_EQ(c.registration.coarse_stride, 1);
  EXPECT_DOUBLE_EQ(c.in_scan_velocity_sigma, 0.0);
  EXPECT_DOUBLE_EQ(c.in_scan_rate_sigma, 0.0);
  EXPECT_DOUBLE_EQ(c.in_scan_angular_acceleration_sigma, 0.0);
  EXPECT_DOUBLE_EQ(c.in_scan_spin_axis_acceleration_sigma, 0.0);
  EXPECT_EQ(ErrorOf(""), "");  // empty document = all defaults
}

TEST(OdometryConfigYaml, MovingPointsAreReadAndTheirMistakesNameTheKey) {
  const OdometryConfig c = io::ParseOdometryConfig(YAML::Load(
      "moving: {enabled: true, margin: 0.5, min_evidence: 7, remove_moved_away_every: 2}\n"));
  EXPECT_TRUE(c.moving.enabled);
  EXPECT_DOUBLE_EQ(c.moving.margin, 0.5);
  EXPECT_EQ(c.moving.min_evidence, 7);
  EXPECT_EQ(c.remove_moved_away_every, 2);
  EXPECT_NE(ErrorOf("moving: {margin: -1}").find("moving.margin: must be > 0"), std::string::npos);
  EXPECT_NE(ErrorOf("moving: {min_evidence_share: 2}").find("moving.min_evidence_share"),
            std::string::npos);
  EXPECT_NE(ErrorOf("moving: {enable: true}").find("moving.enable: unknown key"), std::string::npos);
}

TEST(OdometryConfigYaml, ErrorsNameTheKey) {
  EXPECT_NE(ErrorOf("map: {voxle_size: 1}").find("map.voxle_size: unknown key"), std::string::npos);
  EXPECT_NE(ErrorOf("registration: {max_iterations: many}").find("registration.max_iterations"),
            std::string::npos);
  EXPECT_NE(ErrorOf("registration: {mode: icp}").find("registration.mode: unknown value 'icp'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("map: {max_distance: -5}").find("map.max_distance"), std::string::npos);
  EXPECT_NE(ErrorOf("preprocess: {range_image: {max_auto_cols: -1}}")
                .find("preprocess.range_image.max_auto_cols"),
            std::string::npos);
  EXPECT_NE(ErrorOf("preprocess: {range_image: {max_auto_pixels: -1}}")
                .find("preprocess.range_image.max_auto_pixels"),
            std::string::npos);
  EXPECT_NE(ErrorOf("preprocess: {range_image: {min_auto_cols: 0}}")
                .find("preprocess.range_image.min_auto_cols"),
            std::string::npos);
  EXPECT_NE(ErrorOf("registration: {max_step_extrapolation: 0.5}")
                .find("registration.max_step_extrapolation"),
            std::string::npos);
  EXPECT_NE(ErrorOf("registration: {coarse_stride: 0}")
                .find("registration.coarse_stride: must be in [1, 64] (1 = off)"),
            std::string::npos);
  EXPECT_NE(ErrorOf("motion_prior: {hold_spin_axis_acceleration: true}")
                .find("motion_prior.hold_spin_axis_acceleration: was replaced by "
                      "in_scan_spin_axis_acceleration_sigma"),
            std::string::npos);
  EXPECT_NE(ErrorOf("motion_prior: {in_scan_spin_axis_acceleration_sigma: -0.1}")
                .find("motion_prior.in_scan_spin_axis_acceleration_sigma: must be >= 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf("registration: {line_normal_support: 1.5}")
                .find("registration.line_normal_support: must be in [0, 1]"),
            std::string::npos);
  EXPECT_NE(ErrorOf("registration: {point_shape_min_points: 2}")
                .find("registration.point_shape_min_points: must be >= 3"),
            std::string::npos);
  EXPECT_NE(ErrorOf("motion_prior: {in_scan_rate_sigma: 0}")
                .find("motion_prior.in_scan_velocity_sigma: and in_scan_rate_sigma must both"),
            std::string::npos);
  EXPECT_NE(ErrorOf("motion_prior: {in_scan_velocity_sigma: -1}")
                .find("motion_prior.in_scan_velocity_sigma: must be >= 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf("motion_prior: {in_scan_angular_acceleration_sigma: -2}")
                .find("motion_prior.in_scan_angular_acceleration_sigma: must be >= 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf("motion_prior: {in_scan_velocity_sigma: 0, in_scan_rate_sigma: 0,\n"
                    "               in_scan_angular_acceleration_sigma: 1}")
                .find("motion_prior.in_scan_angular_acceleration_sigma: needs the in-scan motion"),
            std::string::npos);
  EXPECT_NE(ErrorOf("accelerometer: {acceleration_sigma: 0}")
                .find("accelerometer.acceleration_sigma: must be > 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf("accelerometer: {gravity: {trusted_sigma: -1}}")
                .find("accelerometer.gravity.trusted_sigma: must be > 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf("accelerometer: {gravity: {window: 3}}").find("accelerometer.gravity.window: unknown key"),
            std::string::npos);
  EXPECT_NE(ErrorOf("map: {voxel_size: .inf}")
                .find("map.voxel_size: expected a finite number, got '.inf'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("motion_prior: {in_scan_spin_axis_acceleration_sigma: .inf}")
                .find("motion_prior.in_scan_spin_axis_acceleration_sigma: expected a finite number"),
            std::string::npos);
  EXPECT_NE(ErrorOf("registration: {residual_sigma: .nan}")
                .find("registration.residual_sigma: expected a finite number, got '.nan'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("map: [1, 2]").find("map: expected a mapping"), std::string::npos);
  EXPECT_NE(ErrorOf("bogus: 1").find("bogus: unknown key"), std::string::npos);
  EXPECT_NE(ErrorOf("threshold_range_factor: -1").find("threshold_range_factor: must be >= 0"),
            std::string::npos);
}

TEST(OdometryConfigYaml, MissingFileAndBadYamlNameTheFile) {
  try {
    io::LoadOdometryConfig("/nonexistent/odometry.yaml");
    FAIL() << "no exception";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/odometry.yaml"), std::string::npos);
  }
  const auto file = std::filesystem::temp_directory_path() /
                    ("dammloam_cfg_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(file) << "map: {voxel_size: [\n";
  EXPECT_THROW(io::LoadOdometryConfig(file), io::ConfigError);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace dammloam
