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

TEST(OdometryConfigYaml, ShippedDefaultFileLoadsAndEqualsTheDefaults) {
  const auto file = std::filesystem::path(DAMMLOAM_SOURCE_DIR) / "deploy/config/odometry.yaml";
  const OdometryConfig loaded = io::LoadOdometryConfig(file);
  const OdometryConfig defaults;
  EXPECT_EQ(loaded.registration.mode, defaults.registration.mode);
  EXPECT_EQ(loaded.registration.max_iterations, defaults.registration.max_iterations);
  EXPECT_DOUBLE_EQ(loaded.registration.degenerate_eigenvalue_ratio,
                   defaults.registration.degenerate_eigenvalue_ratio);
  EXPECT_DOUBLE_EQ(loaded.map.voxel_size, defaults.map.voxel_size);
  EXPECT_EQ(loaded.map.max_points_per_voxel, defaults.map.max_points_per_voxel);
  EXPECT_EQ(loaded.downsample.target_points, defaults.downsample.target_points);
  EXPECT_NEAR(loaded.preprocess.classifier.majority, defaults.preprocess.classifier.majority, 1e-6);
  EXPECT_DOUBLE_EQ(loaded.preprocess.normals.min_incidence_deg,
                   defaults.preprocess.normals.min_incidence_deg);
  EXPECT_DOUBLE_EQ(loaded.max_time_gap, defaults.max_time_gap);
  EXPECT_DOUBLE_EQ(loaded.threshold_range_factor, defaults.threshold_range_factor);
  EXPECT_EQ(loaded.preprocess.range_image.max_auto_cols,
            defaults.preprocess.range_image.max_auto_cols);
  EXPECT_EQ(loaded.preprocess.range_image.max_auto_pixels,
            defaults.preprocess.range_image.max_auto_pixels);
  EXPECT_EQ(loaded.preprocess.range_image.min_auto_cols,
            defaults.preprocess.range_image.min_auto_cols);
  EXPECT_DOUBLE_EQ(loaded.registration.max_step_extrapolation,
                   defaults.registration.max_step_extrapolation);
  EXPECT_EQ(loaded.registration.coarse_stride, defaults.registration.coarse_stride);
  EXPECT_DOUBLE_EQ(loaded.in_scan_velocity_sigma, defaults.in_scan_velocity_sigma);
  EXPECT_DOUBLE_EQ(loaded.in_scan_rate_sigma, defaults.in_scan_rate_sigma);
  EXPECT_DOUBLE_EQ(loaded.in_scan_angular_acceleration_sigma,
                   defaults.in_scan_angular_acceleration_sigma);
  EXPECT_EQ(loaded.registration.point_shape_min_points,
            defaults.registration.point_shape_min_points);
  EXPECT_DOUBLE_EQ(loaded.registration.line_normal_support,
                   defaults.registration.line_normal_support);
  EXPECT_DOUBLE_EQ(loaded.in_scan_spin_axis_acceleration_sigma,
                   defaults.in_scan_spin_axis_acceleration_sigma);
}

TEST(OdometryConfigYaml, ValuesAreRead) {
  const OdometryConfig c = io::ParseOdometryConfig(YAML::Load(
      "registration: {mode: plane_only, max_iterations: 7, max_step_extrapolation: 1.0,\n"
      "               point_shape_min_points: 12, line_normal_support: 0.25, coarse_stride: 1}\n"
      "map: {voxel_size: 0.4}\n"
      "preprocess: {classifier: {edge_angle_deg: 20}}\ndeskew: false\n"
      "motion_prior: {in_scan_velocity_sigma: 0, in_scan_rate_sigma: 0,\n"
      "               in_scan_angular_acceleration_sigma: 0,\n"
      "               in_scan_spin_axis_acceleration_sigma: 0}\n"));
  EXPECT_EQ(c.registration.mode, RegistrationMode::kPlaneOnly);
  EXPECT_EQ(c.registration.max_iterations, 7);
  EXPECT_DOUBLE_EQ(c.map.voxel_size, 0.4);
  EXPECT_DOUBLE_EQ(c.preprocess.classifier.edge_angle_deg, 20.0);
  EXPECT_FALSE(c.deskew);
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
