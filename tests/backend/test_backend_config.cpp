// The back-end's YAML (deploy/config/backend.yaml, dammloamd's `backend` section): the shipped
// file is the defaults, values reach the structs, mistakes are named.
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "io/backend_config_yaml.hpp"

namespace dammloam {
namespace {

std::string ErrorOf(const std::string& yaml, const std::string& section = "") {
  try {
    io::ParseBackendConfig(YAML::Load(yaml), section);
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(BackendConfigYaml, ShippedFileLoadsAndEqualsTheDefaults) {
  const auto file = std::filesystem::path(DAMMLOAM_SOURCE_DIR) / "deploy/config/backend.yaml";
  const backend::BackendParameters loaded = io::LoadBackendConfig(file);
  const backend::BackendParameters defaults;
  // Field by field (defaulted operator==), so a documented default that drifts from the code's
  // is caught, and the benchmark's numbers do not depend on whether the file is passed.
  EXPECT_TRUE(loaded.loop_closing.keyframes == defaults.loop_closing.keyframes);
  EXPECT_TRUE(loaded.loop_closing.scan_context == defaults.loop_closing.scan_context);
  EXPECT_TRUE(loaded.loop_closing.database == defaults.loop_closing.database);
  EXPECT_TRUE(loaded.loop_closing.verifier.icp == defaults.loop_closing.verifier.icp);
  EXPECT_TRUE(loaded.loop_closing.verifier == defaults.loop_closing.verifier);
  EXPECT_TRUE(loaded.loop_closing.pose_graph == defaults.loop_closing.pose_graph);
  EXPECT_TRUE(loaded.loop_closing == defaults.loop_closing);
  EXPECT_TRUE(loaded.localizer.relocalize_icp == defaults.localizer.relocalize_icp);
  EXPECT_TRUE(loaded.localizer.track_icp == defaults.localizer.track_icp);
  EXPECT_TRUE(loaded.localizer == defaults.localizer);
  EXPECT_TRUE(loaded == defaults);
  EXPECT_NO_THROW(io::ValidateBackendConfig(defaults));
  EXPECT_EQ(ErrorOf(""), "");  // empty document = all defaults
}

TEST(BackendConfigYaml, ValuesAreRead) {
  const backend::BackendParameters c = io::ParseBackendConfig(YAML::Load(R"(
loop_closing:
  keyframes: {min_distance: 0.5}
  scan_context: {rings: 10, sectors: 90, max_range: 25.0}
  database: {exclude_recent: 5}
  verifier:
    icp: {max_iterations: 12, information_kernel: 0.1}
    max_rmse: 0.2
    min_observed_directions: 3
  pose_graph: {max_prune_rounds: 0}
  max_verifications_per_keyframe: 0
  loop_optimize_residual: 0.0
localizer:
  max_registrations: 2
  track_icp: {final_max_correspondence: 0.4, min_direction_support: 5.0}
  track_max_rmse: 0.3
)"));
  const backend::BackendParameters defaults;
  EXPECT_DOUBLE_EQ(c.loop_closing.keyframes.min_distance, 0.5);
  EXPECT_DOUBLE_EQ(c.loop_closing.keyframes.min_rotation_rad,
                   defaults.loop_closing.keyframes.min_rotation_rad);  // absent: default
  EXPECT_EQ(c.loop_closing.scan_context.rings, 10);
  EXPECT_EQ(c.loop_closing.scan_context.sectors, 90);
  EXPECT_DOUBLE_EQ(c.loop_closing.scan_context.max_range, 25.0);
  EXPECT_EQ(c.loop_closing.database.exclude_recent, 5);
  EXPECT_EQ(c.loop_closing.verifier.icp.max_iterations, 12);
  EXPECT_DOUBLE_EQ(c.loop_closing.verifier.icp.information_kernel, 0.1);
  EXPECT_DOUBLE_EQ(c.loop_closing.verifier.max_rmse, 0.2);
  EXPECT_EQ(c.loop_closing.verifier.min_observed_directions, 3);
  EXPECT_EQ(c.loop_closing.pose_graph.max_prune_rounds, 0);
  EXPECT_EQ(c.loop_closing.max_verifications_per_keyframe, 0);
  EXPECT_DOUBLE_EQ(c.loop_closing.loop_optimize_residual, 0.0);
  EXPECT_EQ(c.localizer.max_registrations, 2);
  EXPECT_DOUBLE_EQ(c.localizer.track_icp.final_max_correspondence, 0.4);
  EXPECT_DOUBLE_EQ(c.localizer.track_icp.min_direction_support, 5.0);
  EXPECT_DOUBLE_EQ(c.localizer.track_max_rmse, 0.3);
  EXPECT_TRUE(c.localizer.relocalize_icp == defaults.localizer.relocalize_icp);
}

TEST(BackendConfigYaml, UnknownKeysAreErrorsNamingThem) {
  EXPECT_NE(ErrorOf("loop_closing: {scan_context: {ringz: 20}}")
                .find("loop_closing.scan_context.ringz: unknown key"), std::string::npos);
  EXPECT_NE(ErrorOf("localizer: {track_icp: {information_kernel: 0.05}}")
                .find("localizer.track_icp.information_kernel: unknown key"), std::string::npos)
      << "the localizer never reads the ICP's information";
  EXPECT_NE(ErrorOf("loop_closing: {verifier: {icp: {min_direction_support: 1}}}")
                .find("loop_closing.verifier.icp.min_direction_support: unknown key"),
            std::string::npos) << "the verifier's own min_direction_support overrides it";
  EXPECT_NE(ErrorOf("scan_context: {rings: 20}").find("scan_context: unknown key"),
            std::string::npos) << "keys sit under loop_closing or localizer";
  // In dammloamd's file the section's name leads.
  EXPECT_NE(ErrorOf("loop_closing: {bogus: 1}", "backend")
                .find("backend.loop_closing.bogus: unknown key"), std::string::npos);
}

TEST(BackendConfigYaml, InvalidValuesAreErrorsNamingTheKey) {
  EXPECT_NE(ErrorOf("loop_closing: {scan_context: {rings: -3}}")
                .find("loop_closing.scan_context.rings: must be >= 1"), std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {scan_context: {rings: -3}}", "backend")
                .find("backend.loop_closing.scan_context.rings: must be >= 1"), std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {scan_context: {max_range: 0}}")
                .find("loop_closing.scan_context.max_range: must be > 0"), std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {scan_context: {max_range: .inf}}")
                .find("loop_closing.scan_context.max_range: expected a finite number, got '.inf'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {scan_context: {rings: many}}")
                .find("loop_closing.scan_context.rings: expected an integer, got 'many'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {database: {max_distance: 1.5}}")
                .find("loop_closing.database.max_distance: must be in [0, 1]"), std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {verifier: {min_observed_directions: 4}}")
                .find("loop_closing.verifier.min_observed_directions: must be in [0, 3]"),
            std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {verifier: {icp: {final_max_correspondence: 5.0}}}")
                .find("loop_closing.verifier.icp.final_max_correspondence: must be <= "
                      "initial_max_correspondence"), std::string::npos);
  EXPECT_NE(ErrorOf("loop_closing: {pose_graph: {max_iterations: 0}}")
                .find("loop_closing.pose_graph.max_iterations: must be >= 1"), std::string::npos);
  EXPECT_NE(ErrorOf("localizer: {relocalize_min_inlier_ratio: 2}")
                .find("localizer.relocalize_min_inlier_ratio: must be in [0, 1]"),
            std::string::npos);
  EXPECT_NE(ErrorOf("localizer: {track_icp: {max_iterations: -1}}")
                .find("localizer.track_icp.max_iterations: must be >= 1"), std::string::npos);
  EXPECT_NE(ErrorOf("localizer: [1, 2]").find("localizer: expected a mapping"), std::string::npos);
}

TEST(BackendConfigYaml, FileErrorsNameTheFile) {
  try {
    io::LoadBackendConfig("/nonexistent/backend.yaml");
    FAIL() << "no exception";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/backend.yaml"), std::string::npos);
  }
  const auto file = std::filesystem::temp_directory_path() /
                    ("dammloam_backend_cfg_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(file) << "loop_closing:\n  scan_context:\n    rings: 0\n";
  try {
    io::LoadBackendConfig(file);
    ADD_FAILURE() << "no exception";
  } catch (const io::ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ": loop_closing.scan_context.rings: must be >= 1");
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace dammloam
