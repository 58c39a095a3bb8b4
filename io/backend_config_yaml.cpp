#include "io/backend_config_yaml.hpp"

#include <cmath>
#include <yaml-cpp/yaml.h>

#include "io/yaml_section.hpp"

namespace dammloam::io {
namespace {

using namespace backend;

// The registration settings every ICP of the back-end has. The verifier's direction support is
// its own key (it overrides the ICP's); the localizer never reads the ICP's information.
void ReadIcpCommon(Section& s, IcpConfig& c) {
  s.Get("max_iterations", c.max_iterations);
  s.Get("initial_max_correspondence", c.initial_max_correspondence);
  s.Get("final_max_correspondence", c.final_max_correspondence);
  s.Get("inlier_distance", c.inlier_distance);
  s.Get("convergence_step", c.convergence_step);
}

void ReadVerifierIcp(Section s, IcpConfig& c) {
  ReadIcpCommon(s, c);
  s.Get("information_kernel", c.information_kernel);
  s.RejectUnknownKeys();
}

void ReadLocalizerIcp(Section s, IcpConfig& c) {
  ReadIcpCommon(s, c);
  s.Get("min_direction_support", c.min_direction_support);
  s.RejectUnknownKeys();
}

void ReadKeyframes(Section s, KeyframeSelectorConfig& c) {
  s.Get("min_distance", c.min_distance);
  s.Get("min_rotation_rad", c.min_rotation_rad);
  s.RejectUnknownKeys();
}

void ReadScanContext(Section s, ScanContextConfig& c) {
  s.Get("rings", c.rings);
  s.Get("sectors", c.sectors);
  s.Get("max_range", c.max_range);
  s.Get("sensor_height", c.sensor_height);
  s.RejectUnknownKeys();
}

void ReadDatabase(Section s, ScanContextDatabaseConfig& c) {
  s.Get("exclude_recent", c.exclude_recent);
  s.Get("num_candidates", c.num_candidates);
  s.Get("rebuild_every", c.rebuild_every);
  s.Get("max_distance", c.max_distance);
  s.RejectUnknownKeys();
}

void ReadVerifier(Section s, LoopVerifierConfig& c) {
  ReadVerifierIcp(s.Child("icp"), c.icp);
  s.Get("min_inlier_ratio", c.min_inlier_ratio);
  s.Get("min_inlier_ratio_from_odometry", c.min_inlier_ratio_from_odometry);
  s.Get("max_rmse", c.max_rmse);
  s.Get("drift_per_metre", c.drift_per_metre);
  s.Get("drift_offset", c.drift_offset);
  s.Get("normal_neighbours", c.normal_neighbours);
  s.Get("rotation_drift_per_metre", c.rotation_drift_per_metre);
  s.Get("rotation_drift_offset", c.rotation_drift_offset);
  s.Get("max_level_difference", c.max_level_difference);
  s.Get("min_direction_support", c.min_direction_support);
  s.Get("min_observed_directions", c.min_observed_directions);
  s.Get("min_noise_sigma", c.min_noise_sigma);
  s.Get("free_translation_sigma", c.free_translation_sigma);
  s.Get("free_rotation_sigma", c.free_rotation_sigma);
  s.RejectUnknownKeys();
}

void ReadPoseGraph(Section s, PoseGraphConfig& c) {
  s.Get("loop_huber_scale", c.loop_huber_scale);
  s.Get("loop_prune_threshold", c.loop_prune_threshold);
  s.Get("max_prune_rounds", c.max_prune_rounds);
  s.Get("max_iterations", c.max_iterations);
  s.Get("min_translation_sigma", c.min_translation_sigma);
  s.Get("min_rotation_sigma", c.min_rotation_sigma);
  s.RejectUnknownKeys();
}

void ReadVacated(Section s, VacatedPointsConfig& c) {
  s.Get("enabled", c.enabled);
  s.Get("max_range", c.max_range);
  s.Get("min_range", c.min_range);
  s.Get("margin", c.margin);
  s.Get("margin_per_metre", c.margin_per_metre);
  s.Get("min_views", c.min_views);
  s.RejectUnknownKeys();
}

void ReadLoopClosing(Section s, BackendConfig& c) {
  ReadKeyframes(s.Child("keyframes"), c.keyframes);
  ReadScanContext(s.Child("scan_context"), c.scan_context);
  ReadDatabase(s.Child("database"), c.database);
  ReadVerifier(s.Child("verifier"), c.verifier);
  ReadPoseGraph(s.Child("pose_graph"), c.pose_graph);
  s.Get("keyframe_voxel_size", c.keyframe_voxel_size);
  s.Get("global_map_voxel_size", c.global_map_voxel_size);
  ReadVacated(s.Child("vacated"), c.vacated);
  s.Get("max_verifications_per_keyframe", c.max_verifications_per_keyframe);
  s.Get("proximity_radius", c.proximity_radius);
  s.Get("revisit_drop_distance", c.revisit_drop_distance);
  s.Get("odometry_consistency_chi2", c.odometry_consistency_chi2);
  s.Get("odometry_covariance_scale", c.odometry_covariance_scale);
  s.Get("odometry_heading_drift", c.odometry_heading_drift);
  s.Get("loop_optimize_residual", c.loop_optimize_residual);
  s.Get("loop_translation_sigma", c.loop_translation_sigma);
  s.Get("loop_rotation_sigma", c.loop_rotation_sigma);
  s.RejectUnknownKeys();
}

void ReadLocalizer(Section s, LocalizerConfig& c) {
  s.Get("num_candidates", c.num_candidates);
  s.Get("max_registrations", c.max_registrations);
  s.Get("max_scan_context_distance", c.max_scan_context_distance);
  s.Get("scan_voxel_size", c.scan_voxel_size);
  s.Get("normal_neighbours", c.normal_neighbours);
  ReadLocalizerIcp(s.Child("relocalize_icp"), c.relocalize_icp);
  ReadLocalizerIcp(s.Child("track_icp"), c.track_icp);
  s.Get("relocalize_min_inlier_ratio", c.relocalize_min_inlier_ratio);
  s.Get("relocalize_max_rmse", c.relocalize_max_rmse);
  s.Get("track_min_inlier_ratio", c.track_min_inlier_ratio);
  s.Get("track_max_rmse", c.track_max_rmse);
  s.RejectUnknownKeys();
}

// Range checks with the key's dotted name, relative to the section.
class Checker {
 public:
  explicit Checker(std::string section) : prefix_(section.empty() ? "" : section + ".") {}
  void Require(bool ok, const std::string& field, const std::string& what) const {
    if (!ok) throw ConfigError(prefix_ + field + ": " + what);
  }
  void Positive(double value, const std::string& field) const {
    Require(std::isfinite(value) && value > 0.0, field, "must be > 0");
  }
  void NonNegative(double value, const std::string& field) const {
    Require(std::isfinite(value) && value >= 0.0, field, "must be >= 0");
  }
  void Ratio(double value, const std::string& field) const {
    Require(value >= 0.0 && value <= 1.0, field, "must be in [0, 1]");
  }
  void AtLeast(int value, int min, const std::string& field) const {
    Require(value >= min, field, "must be >= " + std::to_string(min));
  }

  // `own_support`: the ICP's min_direction_support is read (the localizer's); otherwise its
  // information_kernel is (the verifier's).
  void Icp(const IcpConfig& c, const std::string& path, bool own_support) const {
    AtLeast(c.max_iterations, 1, path + ".max_iterations");
    Positive(c.initial_max_correspondence, path + ".initial_max_correspondence");
    Positive(c.final_max_correspondence, path + ".final_max_correspondence");
    Require(c.final_max_correspondence <= c.initial_max_correspondence,
            path + ".final_max_correspondence", "must be <= initial_max_correspondence");
    Positive(c.inlier_distance, path + ".inlier_distance");
    Positive(c.convergence_step, path + ".convergence_step");
    if (own_support) {
      NonNegative(c.min_direction_support, path + ".min_direction_support");
    } else {
      Positive(c.information_kernel, path + ".information_kernel");
    }
  }

 private:
  std::string prefix_;
};

}  // namespace

backend::BackendParameters ParseBackendConfig(const YAML::Node& root, const std::string& section) {
  BackendParameters config;
  Section s(root, section);
  ReadLoopClosing(s.Child("loop_closing"), config.loop_closing);
  ReadLocalizer(s.Child("localizer"), config.localizer);
  s.RejectUnknownKeys();
  ValidateBackendConfig(config, section);
  return config;
}

backend::BackendParameters LoadBackendConfig(const std::filesystem::path& file) {
  const YAML::Node root = LoadYamlFile(file);
  try {
    return ParseBackendConfig(root);
  } catch (const ConfigError& e) {
    throw ConfigError(file.string() + ": " + e.what());
  }
}

void ValidateBackendConfig(const backend::BackendParameters& config, const std::string& section) {
  const Checker check(section);
  const BackendConfig& b = config.loop_closing;
  const std::string lc = "loop_closing.";
  check.NonNegative(b.keyframes.min_distance, lc + "keyframes.min_distance");
  check.NonNegative(b.keyframes.min_rotation_rad, lc + "keyframes.min_rotation_rad");
  check.AtLeast(b.scan_context.rings, 1, lc + "scan_context.rings");
  check.AtLeast(b.scan_context.sectors, 1, lc + "scan_context.sectors");
  check.Positive(b.scan_context.max_range, lc + "scan_context.max_range");
  check.Require(std::isfinite(b.scan_context.sensor_height), lc + "scan_context.sensor_height",
                "must be a finite number");
  check.AtLeast(b.database.exclude_recent, 0, lc + "database.exclude_recent");
  check.AtLeast(b.database.num_candidates, 1, lc + "database.num_candidates");
  check.AtLeast(b.database.rebuild_every, 1, lc + "database.rebuild_every");
  check.Ratio(b.database.max_distance, lc + "database.max_distance");
  const LoopVerifierConfig& v = b.verifier;
  check.Icp(v.icp, lc + "verifier.icp", false);
  check.Ratio(v.min_inlier_ratio, lc + "verifier.min_inlier_ratio");
  check.Ratio(v.min_inlier_ratio_from_odometry, lc + "verifier.min_inlier_ratio_from_odometry");
  check.Positive(v.max_rmse, lc + "verifier.max_rmse");
  check.NonNegative(v.drift_per_metre, lc + "verifier.drift_per_metre");
  check.NonNegative(v.drift_offset, lc + "verifier.drift_offset");
  check.AtLeast(v.normal_neighbours, 3, lc + "verifier.normal_neighbours");
  check.NonNegative(v.rotation_drift_per_metre, lc + "verifier.rotation_drift_per_metre");
  check.NonNegative(v.rotation_drift_offset, lc + "verifier.rotation_drift_offset");
  check.NonNegative(v.max_level_difference, lc + "verifier.max_level_difference");
  check.NonNegative(v.min_direction_support, lc + "verifier.min_direction_support");
  check.Require(v.min_observed_directions >= 0 && v.min_observed_directions <= 3,
                lc + "verifier.min_observed_directions", "must be in [0, 3]");
  check.Positive(v.min_noise_sigma, lc + "verifier.min_noise_sigma");
  check.Positive(v.free_translation_sigma, lc + "verifier.free_translation_sigma");
  check.Positive(v.free_rotation_sigma, lc + "verifier.free_rotation_sigma");
  const PoseGraphConfig& g = b.pose_graph;
  check.Positive(g.loop_huber_scale, lc + "pose_graph.loop_huber_scale");
  check.Positive(g.loop_prune_threshold, lc + "pose_graph.loop_prune_threshold");
  check.AtLeast(g.max_prune_rounds, 0, lc + "pose_graph.max_prune_rounds");
  check.AtLeast(g.max_iterations, 1, lc + "pose_graph.max_iterations");
  check.Positive(g.min_translation_sigma, lc + "pose_graph.min_translation_sigma");
  check.Positive(g.min_rotation_sigma, lc + "pose_graph.min_rotation_sigma");
  check.NonNegative(b.keyframe_voxel_size, lc + "keyframe_voxel_size");  // 0: every point
  check.NonNegative(b.global_map_voxel_size, lc + "global_map_voxel_size");
  check.NonNegative(b.vacated.min_range, lc + "vacated.min_range");
  check.Require(b.vacated.max_range > b.vacated.min_range, lc + "vacated.max_range",
                "must be greater than vacated.min_range");
  check.NonNegative(b.vacated.margin, lc + "vacated.margin");
  check.NonNegative(b.vacated.margin_per_metre, lc + "vacated.margin_per_metre");
  check.AtLeast(b.vacated.min_views, 1, lc + "vacated.min_views");
  check.AtLeast(b.max_verifications_per_keyframe, 0, lc + "max_verifications_per_keyframe");
  check.NonNegative(b.proximity_radius, lc + "proximity_radius");
  check.NonNegative(b.revisit_drop_distance, lc + "revisit_drop_distance");  // 0: keep every cloud
  check.NonNegative(b.odometry_consistency_chi2, lc + "odometry_consistency_chi2");  // 0: no test
  check.Positive(b.odometry_covariance_scale, lc + "odometry_covariance_scale");
  check.NonNegative(b.odometry_heading_drift, lc + "odometry_heading_drift");
  check.NonNegative(b.loop_optimize_residual, lc + "loop_optimize_residual");  // 0: always
  check.NonNegative(b.loop_translation_sigma, lc + "loop_translation_sigma");
  check.NonNegative(b.loop_rotation_sigma, lc + "loop_rotation_sigma");

  const LocalizerConfig& l = config.localizer;
  const std::string lo = "localizer.";
  check.AtLeast(l.num_candidates, 1, lo + "num_candidates");
  check.AtLeast(l.max_registrations, 1, lo + "max_registrations");
  check.Ratio(l.max_scan_context_distance, lo + "max_scan_context_distance");
  check.NonNegative(l.scan_voxel_size, lo + "scan_voxel_size");
  check.AtLeast(l.normal_neighbours, 3, lo + "normal_neighbours");
  check.Icp(l.relocalize_icp, lo + "relocalize_icp", true);
  check.Icp(l.track_icp, lo + "track_icp", true);
  check.Ratio(l.relocalize_min_inlier_ratio, lo + "relocalize_min_inlier_ratio");
  check.Positive(l.relocalize_max_rmse, lo + "relocalize_max_rmse");
  check.Ratio(l.track_min_inlier_ratio, lo + "track_min_inlier_ratio");
  check.Positive(l.track_max_rmse, lo + "track_max_rmse");
}

}  // namespace dammloam::io
