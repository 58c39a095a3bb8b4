// YAML configuration files: the odometry's (io::LoadOdometryConfig), the back-end's
// (io::LoadBackendConfig) and dammloamd's whole file (daemon::LoadConfig, then
// ValidateDaemonConfig), as dammloamd and dammloam-odometry load them from a path.
//
// Input: u8 selector (mod 3: odometry, backend, dammloamd), then the YAML text, written to a
// scratch file. Documented errors: io::ConfigError from the io loaders, std::runtime_error from
// LoadConfig/ValidateDaemonConfig; each must name the file (and the key).
#include <cstdint>

#include "io/backend_config_yaml.hpp"
#include "io/config_yaml.hpp"
#include "services/dammloamd/daemon_config.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::fuzz;

void ExpectNamesFile(const std::exception& e, const fs::path& file) {
  if (std::string_view(e.what()).find(file.string()) == std::string_view::npos) {
    Finding(std::string("config error does not name the file: ") + e.what());
  }
}

void Run(Input& in) {
  const auto selector = in.Get<std::uint8_t>() % 3;
  static const fs::path file = ScratchDir() / "config.yaml";
  WriteFile(file, in.Rest());
  switch (selector) {
    case 0:
      try {
        (void)io::LoadOdometryConfig(file);
      } catch (const io::ConfigError& e) {
        ExpectNamesFile(e, file);
      }
      break;
    case 1:
      try {
        (void)io::LoadBackendConfig(file);
      } catch (const io::ConfigError& e) {
        ExpectNamesFile(e, file);
      }
      break;
    default: {
      daemon::FullConfig config;
      try {
        config = daemon::LoadConfig(file);
      } catch (const std::runtime_error& e) {
        ExpectNamesFile(e, file);
        return;
      }
      // dammloamd reads sensor.meta (a meta.json) before validating; not a parser of this file.
      config.daemon.sensor_meta.clear();
      try {
        daemon::ValidateDaemonConfig(config.daemon);
      } catch (const std::runtime_error&) {
        // documented: names the field
      }
      break;
    }
  }
}

// --- seeds --------------------------------------------------------------------------------

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>&) {
  const fs::path config = SourceDir() / "deploy/config";
  const std::pair<const char*, std::uint8_t> repo[] = {
      {"odometry.yaml", 0}, {"backend.yaml", 1}, {"dammloamd.yaml", 2}};
  for (const auto& [name, selector] : repo) {
    Bytes b;
    b.Put(selector).Append(ReadText(config / name));
    WriteSeed(dir, std::string("repo-") + name, b.data);
  }
  // Small files in each section's style, including the odometry/backend sections of dammloamd's.
  const std::pair<std::uint8_t, const char*> inline_seeds[] = {
      {0, "preprocess:\n  min_range: 0.5\n  range_image: {rows: 64, cols: 0}\n"
          "registration:\n  mode: plane_only\n  max_iterations: 20\nmap:\n  voxel_size: 0.0\n"},
      {1, "loop_closing:\n  scan_context: {rings: 20, sectors: 60, max_range: 80}\n"
          "  verifier:\n    icp: {max_iterations: 30, information_kernel: 0.5}\n"
          "localizer:\n  track_icp: {min_direction_support: 0.1}\n"},
      {2, "dammloamd:\n  domain: 3\n  sensor: {rings: 16, columns: 1800, scan_period: 0.1,\n"
          "           vertical_angles_deg: [15, -15], min_range: 0.5, max_range: 100}\n"
          "  input: {reliable: false, depth: 2, max_points: 100000}\n"
          "  queues: {capacity: 4, max_backlog: 1}\n"
          "  ros2: {enabled: true, points_topic: /velodyne_points, deskew: off}\n"
          "  commands: {enabled: false, allowed_participants: [0110abcd]}\n"
          "odometry:\n  deskew: true\nbackend:\n  localizer: {num_candidates: 5}\n"},
      {2, "{}\n"},
  };
  int n = 0;
  for (const auto& [selector, text] : inline_seeds) {
    Bytes b;
    b.Put(selector).Append(std::string_view(text));
    WriteSeed(dir, "inline-" + std::to_string(n++), b.data);
  }
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
