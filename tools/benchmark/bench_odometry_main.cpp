// dammloam-bench-odometry: accuracy and per-stage speed of the front end on full-length
// simulated runs (the realistic presets, several seeds), with the ablation (point-to-point,
// plane only, classes without degeneracy weights, full with remapping, full) and optional peer
// odometry runners in the same run. Every scan is simulated once and fed to one pipeline per
// mode in turn, so all modes see identical scans under the same machine load and nothing but
// per-scan results is kept in memory.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/benchmark/heap_allocations.hpp"
#include "tools/benchmark/sim_run.hpp"
#include "io/config_yaml.hpp"
#include "io/process_memory.hpp"
#include "io/sequence_io.hpp"
#include "tools/simulate/inertial_meta.hpp"
#include "tools/simulate/presets.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace dammloam;
using bench::Percentiles;

// ---------------------------------------------------------------------------------------------
// Command line

// How a runner is called and how it reports its times.
enum class PeerStyle {
  // `RUNNER SEQ --out poses.tum --timing timing.csv --quiet [ARGS]`: one ms value per scan in
  // timing.csv.
  kBench,
  // The runners of ../shared/peers (kiss_run, genz_run): `RUNNER SEQ_DIR OUT.tum [ARGS]`, every
  // scan's ms in the file named by $ANCHOR_TIMES_OUT and one line
  // `[tag] scans=N per-scan time (ms): mean=X median=Y` on stdout.
  kAnchor,
};

const char* PeerStyleName(PeerStyle style) { return style == PeerStyle::kAnchor ? "anchor" : "bench"; }

struct Peer {
  std::string name;
  std::string path;
  PeerStyle style = PeerStyle::kBench;
  bool style_detected = false;    // from the runner's file name, not named in the spec
  std::vector<std::string> args;  // appended after the fixed command line
  std::optional<double> offset_s;  // --peer-offset; otherwise PeerOffset's default
};

bool HasArg(const Peer& peer, const std::string& arg) {
  return std::find(peer.args.begin(), peer.args.end(), arg) != peer.args.end();
}

// The shared runners are known by their file names; anything else is taken for a bench runner
// (an anchor runner called as a bench one only prints its usage, which said "no result" before).
PeerStyle DetectPeerStyle(const std::string& path) {
  const std::string file = fs::path(path).filename().string();
  return file == "kiss_run" || file == "genz_run" ? PeerStyle::kAnchor : PeerStyle::kBench;
}

// "NAME=[STYLE:]PATH[:ARG,ARG...]", STYLE "anchor" or "bench"; without it, DetectPeerStyle.
std::optional<Peer> ParsePeer(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) return std::nullopt;
  Peer peer;
  peer.name = text.substr(0, eq);
  std::string rest = text.substr(eq + 1);
  peer.style_detected = true;
  for (const PeerStyle style : {PeerStyle::kAnchor, PeerStyle::kBench}) {
    const std::string prefix = std::string(PeerStyleName(style)) + ":";
    if (rest.compare(0, prefix.size(), prefix) == 0) {
      peer.style = style;
      peer.style_detected = false;
      rest = rest.substr(prefix.size());
      break;
    }
  }
  const auto colon = rest.find(':');
  peer.path = rest.substr(0, colon);
  if (colon != std::string::npos) {
    std::stringstream args(rest.substr(colon + 1));
    for (std::string arg; std::getline(args, arg, ',');) {
      if (!arg.empty()) peer.args.push_back(arg);
    }
  }
  if (peer.path.empty()) return std::nullopt;
  if (peer.style_detected) peer.style = DetectPeerStyle(peer.path);
  return peer;
}

// When within a scan the runner's pose is, as seconds after the scan-start stamp it writes. The
// truth is taken at stamp + offset. KISS-ICP deskews every point to the scan's END and reports
// that pose at the start stamp (../shared/peers/README.md); GenZ-ICP (deskew off, or deskewed to
// 0.5) and KISS-ICP without deskew fit the scan as a whole: about mid-scan. Unknown runners: 0.
double PeerOffset(const Peer& peer, double scan_period) {
  if (peer.offset_s) return *peer.offset_s;
  const std::string file = fs::path(peer.path).filename().string();
  if (file == "kiss_run") return HasArg(peer, "--no-deskew") ? 0.5 * scan_period : scan_period;
  if (file == "genz_run") return 0.5 * scan_period;
  return 0.0;
}

// PeerOffset in words, for the run's header.
std::string PeerOffsetText(const Peer& peer) {
  if (peer.offset_s) return std::to_string(*peer.offset_s) + " s (--peer-offset)";
  const std::string file = fs::path(peer.path).filename().string();
  if (file == "kiss_run" && !HasArg(peer, "--no-deskew")) {
    return "1 scan period (KISS-ICP's pose is the sensor's at the scan's end)";
  }
  if (file == "kiss_run" || file == "genz_run") return "0.5 scan period (the pose of the scan as a whole: mid-scan)";
  return "0 s (scan start; --peer-offset NAME=SECONDS to change)";
}

// "NAME=SECONDS" of --peer-offset.
bool ParsePeerOffset(const std::string& text, std::vector<Peer>& peers) {
  const auto eq = text.find('=');
  if (eq == std::string::npos) return false;
  const std::string name = text.substr(0, eq), value = text.substr(eq + 1);
  char* end = nullptr;
  const double seconds = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(seconds)) return false;
  for (Peer& p : peers) {
    if (p.name == name) {
      p.offset_s = seconds;
      return true;
    }
  }
  return false;
}

struct Options {
  std::vector<std::string> presets{"handheld-corridor", "wheeled-corridor", "legged-tunnel",
                                   "wheeled-zigzag"};
  std::vector<std::string> scenes;  // legacy: constant-speed scenes, --scans each
  std::vector<std::string> sensors{"os1-64", "vlp-16"};
  std::vector<std::string> modes{"point_to_point", "plane_only", "classes_no_degeneracy",
                                 "full_remap", "full"};
  std::vector<std::uint64_t> seeds;
  std::uint64_t seed = 1;
  std::optional<int> scans;
  std::vector<std::string> peer_specs;
  std::vector<std::string> peer_offset_specs;
  std::vector<Peer> peers;
  std::string cache_dir;
  std::string json_path;
  std::string config_path;
  std::vector<std::string> variant_specs;  // NAME=PATH: another config, as one more row
  bool per_scan = false;
  bool no_remap = false;
  bool quiet = false;
};

// One row group: a preset (or legacy scene) on one sensor.
struct Group {
  std::string label;        // preset or scene name
  bool preset = false;
  sim::Preset preset_def;   // when preset
  sim::SceneKind scene = sim::SceneKind::Corridor;
  sim::SensorSpec sensor;
  int scans = 0;
};

// ---------------------------------------------------------------------------------------------
// Results

// One mode or peer on one seed: accuracy and the per-scan samples that get pooled over seeds.
struct SeedResult {
  std::uint64_t seed = 0;
  std::size_t scans = 0;
  bench::TrajectoryErrors errors;
  std::vector<double> features_ms, registration_ms, map_update_ms, total_ms, iterations, map_points;
  std::vector<double> searched_points;  // map lookups per scan
  std::vector<double> allocations;      // heap allocations per scan after the warm-up
  std::size_t registered = 0;
  std::size_t degenerate = 0;
  std::string failure;  // peers: why the run gave no result
  bool has_truth = false;  // the scene has actors: moving_labels is scored
  bench::MovingLabelScore moving_labels;
};

struct Row {
  std::string name;
  bool peer = false;
  std::vector<SeedResult> seeds;
  double offset_s = 0.0;  // peers: their stamps + offset_s are paired with the truth (PeerOffset)
};

struct GroupResult {
  Group group;
  std::vector<Row> rows;  // modes first, then peers
  // VmRSS after the last scan with every mode's pipeline alive (max over seeds); VmHWM so far.
  double rss_end_mib = 0.0, rss_peak_mib = 0.0;
  double sim_ms_per_scan = 0.0;  // median over seeds of the time to produce a scan
  bool from_cache = false;
};

// The middle value, or the mean of the two middle values of an even count (as evo's median).
double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t mid = v.size() / 2;
  return v.size() % 2 == 1 ? v[mid] : 0.5 * (v[mid - 1] + v[mid]);
}

std::vector<double> Pool(const Row& row, std::vector<double> SeedResult::*field) {
  std::vector<double> all;
  for (const SeedResult& s : row.seeds) all.insert(all.end(), (s.*field).begin(), (s.*field).end());
  return all;
}

struct Aggregate {
  std::size_t seeds = 0;  // seeds with a result
  double ape_rmse_median = 0, ape_rmse_min = 0, ape_rmse_max = 0, ape_max = 0;
  double rpe_rmse_median = 0;
  double worst_frame_m = 0, median_frame_m = 0, worst_ratio = 0;
  std::uint64_t worst_frame_seed = 0;
  std::size_t worst_frame_index = 0;
  Percentiles features, registration, map_update, total;
  double iterations_median = 0, map_median = 0, map_max = 0;
  double searched_points_median = 0;
  Percentiles allocations;  // per scan after the warm-up (kAllocationWarmUpScans)
  bool allocations_counted = false;
  double degenerate_share = 0, registered_share = 0;
  // Moving labels against the simulator's truth, pooled over seeds, and the worst seed's.
  bool has_truth = false;
  bench::MovingLabelScore moving_labels;
  double worst_precision = 1.0, worst_recall = 1.0, worst_static_flagged = 0.0;
};

Aggregate Summarise(const Row& row) {
  Aggregate a;
  std::vector<double> ape_rmse, rpe_rmse, frames;
  std::size_t scans = 0, degenerate = 0, registered = 0;
  for (const SeedResult& s : row.seeds) {
    if (!s.failure.empty()) continue;
    ++a.seeds;
    ape_rmse.push_back(s.errors.ape_rmse);
    rpe_rmse.push_back(s.errors.rpe_rmse);
    a.ape_max = std::max(a.ape_max, s.errors.ape_max);
    if (s.errors.worst_frame_m >= a.worst_frame_m) {
      a.worst_frame_m = s.errors.worst_frame_m;
      a.worst_frame_seed = s.seed;
      a.worst_frame_index = s.errors.worst_frame_index;
    }
    frames.insert(frames.end(), s.errors.frame_errors.begin(), s.errors.frame_errors.end());
    scans += s.scans;
    degenerate += s.degenerate;
    registered += s.registered;
    if (s.has_truth) {
      a.has_truth = true;
      a.moving_labels += s.moving_labels;
      a.worst_precision = std::min(a.worst_precision, s.moving_labels.Precision());
      a.worst_recall = std::min(a.worst_recall, s.moving_labels.Recall());
      a.worst_static_flagged = std::max(a.worst_static_flagged, s.moving_labels.StaticFlaggedShare());
    }
  }
  if (a.seeds == 0) return a;
  a.ape_rmse_median = Median(ape_rmse);
  a.ape_rmse_min = *std::min_element(ape_rmse.begin(), ape_rmse.end());
  a.ape_rmse_max = *std::max_element(ape_rmse.begin(), ape_rmse.end());
  a.rpe_rmse_median = Median(rpe_rmse);
  a.median_frame_m = Median(frames);
  a.worst_ratio = a.median_frame_m > 0 ? a.worst_frame_m / a.median_frame_m : 0.0;
  a.features = bench::ComputePercentiles(Pool(row, &SeedResult::features_ms));
  a.registration = bench::ComputePercentiles(Pool(row, &SeedResult::registration_ms));
  a.map_update = bench::ComputePercentiles(Pool(row, &SeedResult::map_update_ms));
  a.total = bench::ComputePercentiles(Pool(row, &SeedResult::total_ms));
  a.iterations_median = Median(Pool(row, &SeedResult::iterations));
  a.searched_points_median = Median(Pool(row, &SeedResult::searched_points));
  const std::vector<double> allocations = Pool(row, &SeedResult::allocations);
  a.allocations_counted = !allocations.empty();
  a.allocations = bench::ComputePercentiles(allocations);
  const Percentiles map = bench::ComputePercentiles(Pool(row, &SeedResult::map_points));
  a.map_median = map.median;
  a.map_max = map.max;
  a.degenerate_share = scans ? static_cast<double>(degenerate) / static_cast<double>(scans) : 0.0;
  a.registered_share = scans ? static_cast<double>(registered) / static_cast<double>(scans) : 0.0;
  return a;
}

// Scans before the steady state: the map, the pools and every per-scan buffer still grow.
constexpr std::size_t kAllocationWarmUpScans = 100;

SeedResult FromTrace(std::uint64_t seed, const bench::ScanStream& stream, const bench::ModeTrace& trace) {
  SeedResult r;
  r.seed = seed;
  r.scans = trace.scans.size();
  r.errors = bench::EvaluateEstimate(stream.ground_truth, trace.Estimate());
  r.has_truth = static_cast<bool>(stream.labelled_scan);
  r.moving_labels = trace.MovingLabels();
  for (std::size_t i = kAllocationWarmUpScans;
       bench::HeapAllocationsCounted() && i < trace.scans.size(); ++i) {
    r.allocations.push_back(static_cast<double>(trace.scans[i].allocations));
  }
  for (const bench::ScanRecord& s : trace.scans) {
    const StageTimings& t = s.timings;
    r.features_ms.push_back(t.projection_ms + t.normals_ms + t.classification_ms);
    r.registration_ms.push_back(t.registration_ms);
    r.map_update_ms.push_back(t.map_update_ms);
    r.total_ms.push_back(t.total_ms);
    r.iterations.push_back(s.iterations);
    r.searched_points.push_back(static_cast<double>(s.searched_points));
    r.map_points.push_back(static_cast<double>(s.map_points));
    if (Registered(s.status)) ++r.registered;
    if (s.degenerate) ++r.degenerate;
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// Peers

// Runs argv with stdout and stderr to `log` and `env` ("KEY=VALUE") added to this process's
// environment. Returns the exit code; throws, saying why, when there is none.
int RunProcess(const std::vector<std::string>& argv, const std::vector<std::string>& env,
               const fs::path& log) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<char*> envp;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry = *e;
    const bool replaced = std::any_of(env.begin(), env.end(), [&](const std::string& kv) {
      return entry.compare(0, kv.find('=') + 1, kv, 0, kv.find('=') + 1) == 0;
    });
    if (!replaced) envp.push_back(*e);
  }
  for (const std::string& kv : env) envp.push_back(const_cast<char*>(kv.c_str()));
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int err = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(err));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("lost " + argv[0] + ": " + std::strerror(errno));
  }
  if (WIFSIGNALED(status)) {
    throw std::runtime_error(argv[0] + " was killed by signal " + std::to_string(WTERMSIG(status)));
  }
  return WEXITSTATUS(status);
}

// One ms value per line; blank lines and headers are skipped. `what` names the file's role in
// the error, so that an empty file says which output the runner did not give.
std::vector<double> ReadTimes(const fs::path& file, const std::string& what) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("no per-scan times: " + what + " " + file.string() + " was not written");
  std::vector<double> ms;
  for (std::string line; std::getline(in, line);) {
    char* end = nullptr;
    const double v = std::strtod(line.c_str(), &end);
    if (end != line.c_str()) ms.push_back(v);
  }
  if (ms.empty()) throw std::runtime_error("no per-scan times: " + what + " " + file.string() + " is empty");
  return ms;
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The end of a runner's output for an error message, or a note that there was none.
std::string Tail(const fs::path& file, std::size_t max_chars = 600) {
  std::string s = ReadText(file);
  const auto last = s.find_last_not_of(" \t\r\n");
  if (last == std::string::npos) return "(it printed nothing)";
  s.erase(last + 1);
  return "output: " + (s.size() > max_chars ? "..." + s.substr(s.size() - max_chars) : s);
}

// The scan count of an anchor runner's summary line "[tag] scans=N per-scan time (ms): ...".
std::optional<std::size_t> AnchorScans(const std::string& output) {
  const auto at = output.find("] scans=");
  if (at == std::string::npos || output.find("per-scan time (ms)", at) == std::string::npos) return std::nullopt;
  return std::strtoull(output.c_str() + at + 8, nullptr, 10);
}

// What a peer run leaves in the work directory.
struct PeerFiles {
  fs::path poses, times, log;
};

std::vector<std::string> PeerArgv(const Peer& peer, const fs::path& sequence, const PeerFiles& f) {
  std::vector<std::string> argv{peer.path, sequence.string(), f.poses.string()};
  if (peer.style == PeerStyle::kBench) {
    argv = {peer.path, sequence.string(), "--out", f.poses.string(), "--timing", f.times.string(), "--quiet"};
  }
  argv.insert(argv.end(), peer.args.begin(), peer.args.end());
  return argv;
}

// The runner's per-scan times, checked against its own summary (anchor) and its pose count.
std::vector<double> PeerTimes(const Peer& peer, const PeerFiles& f, std::size_t poses) {
  std::vector<double> ms;
  if (peer.style == PeerStyle::kAnchor) {
    const auto scans = AnchorScans(ReadText(f.log));
    if (!scans) {
      throw std::runtime_error("no '[tag] scans=N per-scan time (ms): ...' line, as the runners of "
                               "../shared/peers print: is it one? " + Tail(f.log));
    }
    ms = ReadTimes(f.times, "ANCHOR_TIMES_OUT");
    if (ms.size() != *scans) {
      throw std::runtime_error("it says scans=" + std::to_string(*scans) + " but wrote " +
                               std::to_string(ms.size()) + " times to ANCHOR_TIMES_OUT");
    }
  } else {
    ms = ReadTimes(f.times, "--timing");
  }
  if (ms.size() != poses) {
    throw std::runtime_error(std::to_string(poses) + " poses but " + std::to_string(ms.size()) + " per-scan times");
  }
  return ms;
}

// A shared runner called in the bench convention takes "--out" for its output file and the
// poses' path for an unknown option (or prints its usage): say which convention it wants.
std::string StyleHint(const Peer& peer, const PeerFiles& f) {
  const std::string output = ReadText(f.log);
  if (peer.style == PeerStyle::kBench && (output.find("unknown option " + f.poses.string()) != std::string::npos ||
                                          output.find("SEQ_DIR OUT.tum") != std::string::npos)) {
    return " (it reads `RUNNER SEQ_DIR OUT.tum`, the ../shared/peers convention: give --peer " + peer.name +
           "=anchor:" + peer.path + ")";
  }
  return "";
}

// The truth at any time of the run (the simulator's trajectory): the peers' poses are taken at
// their stamps plus an offset, between the scan starts of gt.tum.
using TruthAt = std::function<Eigen::Isometry3d(double)>;

SeedResult RunPeer(const Peer& peer, std::uint64_t seed, const fs::path& sequence, const TruthAt& truth_at,
                   double offset_s, const fs::path& work) {
  SeedResult r;
  r.seed = seed;
  const PeerFiles f{work / (peer.name + ".tum"), work / (peer.name + ".times.txt"), work / (peer.name + ".log")};
  std::error_code ec;
  fs::remove(f.poses, ec);  // a file left by the seed before must not pass for this one's
  fs::remove(f.times, ec);
  try {
    const std::vector<std::string> env{"ANCHOR_TIMES_OUT=" + f.times.string()};
    const int code = RunProcess(PeerArgv(peer, sequence, f), env, f.log);
    if (code != 0) {
      throw std::runtime_error("exit code " + std::to_string(code) + StyleHint(peer, f) + "; " + Tail(f.log));
    }
    if (!fs::exists(f.poses) || fs::file_size(f.poses) == 0) {
      throw std::runtime_error("no poses in " + f.poses.string() + "; " + Tail(f.log));
    }
    std::vector<io::StampedPose> estimate = io::ReadTum(f.poses);
    r.total_ms = PeerTimes(peer, f, estimate.size());
    std::vector<io::StampedPose> truth;
    for (io::StampedPose& p : estimate) {
      p.t += offset_s;
      truth.push_back({p.t, truth_at(p.t)});
    }
    r.scans = estimate.size();
    r.registered = estimate.size();
    r.errors = bench::EvaluateEstimate(truth, estimate);
  } catch (const std::exception& e) {
    r.failure = e.what();
    std::fprintf(stderr, "warning: peer %s (%s), seed %llu: %s\n", peer.name.c_str(), peer.path.c_str(),
                 static_cast<unsigned long long>(seed), r.failure.c_str());
  }
  return r;
}

// A temporary directory removed when this goes out of scope.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "dammloam-bench-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary directory");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// ---------------------------------------------------------------------------------------------
// Running a group

// Frame-to-frame motion error per scan, to see where tracking goes wrong.
void PrintPerScan(const bench::ScanStream& stream, const bench::ModeTrace& run) {
  std::printf("  per scan, %s:\n", run.mode.c_str());
  for (std::size_t i = 1; i < run.scans.size(); ++i) {
    const bench::ScanRecord& r = run.scans[i];
    const Eigen::Isometry3d gt = stream.ground_truth[i - 1].T.inverse() * stream.ground_truth[i].T;
    const Eigen::Isometry3d est = run.scans[i - 1].T_world_sensor.inverse() * r.T_world_sensor;
    const Eigen::Vector3d e = (gt.inverse() * est).translation();
    std::printf("    %4zu %-12s it %2d corr %5u alpha %.2f  gt dt (%6.3f %6.3f %6.3f)  err (%6.3f "
                "%6.3f %6.3f)  lambda (%.0f %.0f %.0f) classes u%u g%u r%u w%u e%u m%u\n",
                i, std::string(Name(r.status)).c_str(), r.iterations, r.num_correspondences, r.alpha,
                gt.translation().x(), gt.translation().y(), gt.translation().z(), e.x(), e.y(), e.z(),
                r.eigenvalues[0], r.eigenvalues[1], r.eigenvalues[2], r.class_counts[0],
                r.class_counts[1], r.class_counts[2], r.class_counts[3], r.class_counts[4],
                r.class_counts[5]);
  }
}

std::unique_ptr<sim::Simulator> MakeSimulator(const Group& g, std::uint64_t seed) {
  if (g.preset) return std::make_unique<sim::Simulator>(g.preset_def, g.sensor, seed);
  sim::SimOptions options;
  options.seed = seed;
  options.num_scans = g.scans;
  return std::make_unique<sim::Simulator>(g.scene, g.sensor, options);
}

// Cache entry of one seed: complete when it has `scans` scans and gt.tum (written last).
fs::path CachePath(const Options& o, const Group& g, std::uint64_t seed) {
  return fs::path(o.cache_dir) / (g.label + "_" + g.sensor.name + "_seed" + std::to_string(seed) + "_" +
                                  std::to_string(g.scans) + "scans");
}

bool CacheComplete(const fs::path& dir, int scans) {
  try {
    const auto reader = io::SequenceReader::Open(dir);
    const auto gt = reader.ReadGroundTruth();
    return reader.size() == static_cast<std::size_t>(scans) && gt && gt->size() == reader.size();
  } catch (const std::exception&) {
    return false;
  }
}

GroupResult RunGroup(const Options& o, const Group& g, const std::vector<OdometryConfig>& configs,
                     const std::vector<std::string>& row_names) {
  GroupResult result;
  result.group = g;
  for (const std::string& name : row_names) result.rows.push_back({name, false, {}});
  for (const Peer& p : o.peers) result.rows.push_back({p.name, true, {}});
  std::vector<double> sim_ms;
  for (const std::uint64_t seed : o.seeds) {
    const auto seed_start = std::chrono::steady_clock::now();
    std::optional<TempDir> work;
    if (!o.peers.empty()) work.emplace();
    fs::path sequence_dir;  // on disk when peers or the cache need it
    std::unique_ptr<sim::Simulator> simulator;
    bench::ScanStream stream;
    std::unique_ptr<io::SequenceWriter> writer;
    if (!o.cache_dir.empty()) {
      sequence_dir = CachePath(o, g, seed);
      if (CacheComplete(sequence_dir, g.scans)) {
        stream = bench::SequenceStream(sequence_dir.string());
        result.from_cache = true;
      }
    } else if (work) {
      sequence_dir = work->path() / "sequence";
    }
    if (!stream.scan) {
      simulator = MakeSimulator(g, seed);
      stream = bench::SimulatedStream(*simulator, g.scans);
      if (!sequence_dir.empty()) {
        // imu.csv / wheel.csv beside the scans, as dammloam-simulate writes them (issue 55).
        io::SequenceMeta meta{g.sensor.name, stream.model, io::PointLayout::kXYZITR};
        const sim::InertialStreams streams = sim::SimulateInertialStreams(*simulator, g.scans, {});
        sim::DescribeStreams(streams, &meta);
        writer = std::make_unique<io::SequenceWriter>(sequence_dir, meta, /*overwrite=*/true);
        if (streams.imu) writer->WriteImu(*streams.imu);
        if (streams.wheel) writer->WriteWheel(*streams.wheel);
      }
    }
    // Time spent producing scans (simulating or reading) = wall time minus the pipelines'.
    double produce_ms = 0.0;
    auto timed_stream = stream;
    timed_stream.scan = [&stream, &produce_ms](std::size_t i) {
      const auto start = std::chrono::steady_clock::now();
      Scan scan = stream.scan(i);
      produce_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      return scan;
    };
    if (stream.labelled_scan) {
      timed_stream.labelled_scan = [&stream, &produce_ms](std::size_t i, std::vector<std::uint8_t>& truth) {
        const auto start = std::chrono::steady_clock::now();
        Scan scan = stream.labelled_scan(i, truth);
        produce_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        return scan;
      };
    }
    const auto on_scan = [&writer](const Scan& scan) {
      if (writer) writer->Write(scan);
    };
    const std::size_t step = std::max<std::size_t>(100, stream.size() / 8);
    const auto progress = [&](std::size_t done) {
      // All pipelines (maps, filters) are still alive after the last scan: the process's RSS now.
      if (done == stream.size()) result.rss_end_mib = std::max(result.rss_end_mib, bench::ProcStatusMiB("VmRSS"));
      if (o.quiet || (done % step != 0 && done != stream.size())) return;
      std::fprintf(stderr, "  %s / %s seed %llu: %zu/%zu scans, %.0f s\n", g.label.c_str(),
                   g.sensor.name.c_str(), static_cast<unsigned long long>(seed), done, stream.size(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - seed_start).count());
    };
    const std::vector<bench::ModeTrace> traces = bench::StreamModes(timed_stream, configs, on_scan, progress);
    if (writer) writer->WriteGroundTruth(stream.ground_truth);
    sim_ms.push_back(stream.size() ? produce_ms / static_cast<double>(stream.size()) : 0.0);
    for (std::size_t m = 0; m < traces.size(); ++m) {
      if (o.per_scan) PrintPerScan(stream, traces[m]);
      result.rows[m].seeds.push_back(FromTrace(seed, stream, traces[m]));
    }
    // A cached sequence was read without a simulator: its truth comes from the same one.
    if (!o.peers.empty() && !simulator) simulator = MakeSimulator(g, seed);
    const TruthAt truth_at = [&simulator](double t) { return simulator->PoseAt(t); };
    for (std::size_t p = 0; p < o.peers.size(); ++p) {
      Row& row = result.rows[traces.size() + p];
      row.offset_s = PeerOffset(o.peers[p], stream.model.scan_period);
      if (!o.quiet) std::fprintf(stderr, "  running peer %s on seed %llu\n", o.peers[p].name.c_str(),
                                 static_cast<unsigned long long>(seed));
      row.seeds.push_back(RunPeer(o.peers[p], seed, sequence_dir, truth_at, row.offset_s, work->path()));
    }
  }
  result.sim_ms_per_scan = Median(sim_ms);
  // VmHWM lags the split per-thread RSS counters slightly: never report it below the RSS seen.
  result.rss_peak_mib = std::max(bench::ProcStatusMiB("VmHWM"), result.rss_end_mib);
  return result;
}

// ---------------------------------------------------------------------------------------------
// Output

std::string Kilo(double n) {
  char buf[32];
  if (n >= 1e6) std::snprintf(buf, sizeof buf, "%.1fM", n / 1e6);
  else if (n >= 1e3) std::snprintf(buf, sizeof buf, "%.0fk", n / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f", n);
  return buf;
}

// One decimal: lookups per scan differ by a few percent between builds.
std::string Thousands(double n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1fk", n / 1e3);
  return buf;
}

std::string SeedList(const std::vector<std::uint64_t>& seeds) {
  std::string s;
  for (const auto seed : seeds) s += (s.empty() ? "" : ",") + std::to_string(seed);
  return s;
}

// Against the simulator's truth (bench::MovingLabelScore): labelled moving where the actor moved
// more than 0.3 m in the last second.
void PrintMovingLabels(const Aggregate& a) {
  const bench::MovingLabelScore& m = a.moving_labels;
  std::printf("  %-22s moving labels: precision %.1f %%, recall %.1f %%, static labelled moving "
              "%.3f %% (pooled; worst seed %.1f / %.1f / %.3f %%; %zu moving, %zu static points%s)\n",
              "", 100.0 * m.Precision(), 100.0 * m.Recall(), 100.0 * m.StaticFlaggedShare(),
              100.0 * a.worst_precision, 100.0 * a.worst_recall, 100.0 * a.worst_static_flagged,
              m.moving_found + m.moving_missed, m.static_points,
              m.mismatched_scans ? ", some scans not scored" : "");
}

void PrintAllocations(const Aggregate& a) {
  std::printf("  %-22s heap allocations per scan after scan %zu: median %.0f, p99 %.0f, max %.0f\n", "",
              kAllocationWarmUpScans, a.allocations.median, a.allocations.p99, a.allocations.max);
}

// "kiss +0.100s": a peer's row names the time offset its poses were evaluated at.
std::string PeerLabel(const Row& row) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %+.3fs", row.name.c_str(), row.offset_s);
  return buf;
}

// The first seed's failure, on one line: a row without a result says why where it is read.
std::string FirstFailure(const Row& row) {
  for (const SeedResult& s : row.seeds) {
    if (s.failure.empty()) continue;
    std::string line = "seed " + std::to_string(s.seed) + ": " + s.failure;
    std::replace(line.begin(), line.end(), '\n', ' ');
    return line;
  }
  return "no seed ran";
}

void PrintGroup(const Options& o, const GroupResult& r) {
  const Group& g = r.group;
  std::printf("\n%s / %s: %d scans x seeds %s (%s %.1f ms/scan), RSS at end %.0f MiB (peak %.0f), all modes\n",
              g.label.c_str(), g.sensor.name.c_str(), g.scans, SeedList(o.seeds).c_str(),
              r.from_cache ? "read from cache" : "simulated", r.sim_ms_per_scan, r.rss_end_mib,
              r.rss_peak_mib);
  std::printf("  %-22s %6s %6s %13s %6s %14s | %-11s %-11s %-11s %-11s %6s | %3s %7s %9s %5s\n",
              "mode", "APE", "APEmax", "APE spread", "RPE", "worst frame", "feat ms", "reg ms",
              "map ms", "total ms", "x base", "it", "lookups", "map pts", "degen");
  std::printf("  %-22s %6s %6s %13s %6s %14s | %-11s %-11s %-11s %-11s %6s | %3s %7s %9s %5s\n",
              "", "med m", "m", "min-max m", "med m", "m (x median)", "med/p99", "med/p99",
              "med/p99", "med/p99", "", "med", "med", "med/max", "");
  const Aggregate baseline = Summarise(r.rows.front());
  // Peers are compared with our full mode, or the last mode when full is not run.
  std::optional<Aggregate> full;
  std::string full_name;
  for (const Row& row : r.rows) {
    if (!row.peer && (row.name == "full" || full_name != "full")) {
      full = Summarise(row);
      full_name = row.name;
    }
  }
  for (const Row& row : r.rows) {
    const Aggregate a = Summarise(row);
    const std::string name = row.peer ? PeerLabel(row) : row.name;
    if (a.seeds == 0) {
      std::printf("  %-22s no result: %s\n", name.c_str(), FirstFailure(row).c_str());
      continue;
    }
    char spread[32], worst[32];
    std::snprintf(spread, sizeof spread, "%.3f-%.3f", a.ape_rmse_min, a.ape_rmse_max);
    std::snprintf(worst, sizeof worst, "%.3f (x%.0f)", a.worst_frame_m, a.worst_ratio);
    std::printf("  %-22s %6.3f %6.3f %13s %6.3f %14s | ", name.c_str(), a.ape_rmse_median, a.ape_max,
                spread, a.rpe_rmse_median, worst);
    if (row.peer) {
      const double ratio = a.total.median > 0 && full ? full->total.median / a.total.median : 0.0;
      std::printf("%-11s %-11s %-11s %5.1f/%-5.1f x%5.2f | %s/peer x%.2f%s\n", "", "", "", a.total.median,
                  a.total.p99,
                  baseline.total.median > 0 ? a.total.median / baseline.total.median : 0.0,
                  full_name.c_str(), ratio, a.seeds < o.seeds.size() ? " (some seeds failed)" : "");
    } else {
      std::printf("%4.1f/%-6.1f %4.1f/%-6.1f %4.1f/%-6.1f %5.1f/%-5.1f x%5.2f | ",
                  a.features.median, a.features.p99, a.registration.median, a.registration.p99,
                  a.map_update.median, a.map_update.p99, a.total.median, a.total.p99,
                  baseline.total.median > 0 ? a.total.median / baseline.total.median : 0.0);
      std::printf("%3.0f %7s %4s/%-4s %4.0f%%\n", a.iterations_median,
                  Thousands(a.searched_points_median).c_str(), Kilo(a.map_median).c_str(),
                  Kilo(a.map_max).c_str(), 100.0 * a.degenerate_share);
      if (a.has_truth) PrintMovingLabels(a);
      if (a.allocations_counted) PrintAllocations(a);
    }
  }
  if (!o.peers.empty()) {
    std::printf("  peers: APE of their poses at stamp + the offset in their row, against the simulator's "
                "truth at that time; ms: their own per-scan times\n");
  }
  std::fflush(stdout);
}

nlohmann::json ToJson(const Percentiles& p) {
  return {{"median", p.median}, {"p95", p.p95}, {"p99", p.p99}, {"max", p.max}};
}

nlohmann::json ToJson(const SeedResult& s) {
  nlohmann::json j{{"seed", s.seed}, {"scans", s.scans}};
  if (!s.failure.empty()) {
    j["failure"] = s.failure;
    return j;
  }
  j["ape_rmse_m"] = s.errors.ape_rmse;
  j["ape_max_m"] = s.errors.ape_max;
  j["rpe_rmse_m"] = s.errors.rpe_rmse;
  j["drift_percent"] = s.errors.drift_percent;
  j["median_frame_m"] = s.errors.median_frame_m;
  j["worst_frame_m"] = s.errors.worst_frame_m;
  j["worst_frame_index"] = s.errors.worst_frame_index;
  j["noise_worst_to_median_frame"] = s.errors.noise_worst_ratio;
  j["noise_worst_to_median_frame_p95"] = s.errors.noise_worst_ratio_p95;
  j["pairs"] = s.errors.pairs;
  j["registered"] = s.registered;
  j["degenerate"] = s.degenerate;
  j["total_ms"] = ToJson(bench::ComputePercentiles(s.total_ms));
  return j;
}

nlohmann::json ToJson(const GroupResult& r, const Options& o) {
  const Group& g = r.group;
  nlohmann::json j{{g.preset ? "preset" : "scene", g.label},
                   {"scene", std::string(sim::SceneName(g.preset ? g.preset_def.scene : g.scene))},
                   {"sensor", g.sensor.name},
                   {"scans", g.scans},
                   {"seeds", o.seeds},
                   {"from_cache", r.from_cache},
                   {"produce_ms_per_scan", r.sim_ms_per_scan},
                   {"rss_end_mib", r.rss_end_mib},
                   {"rss_peak_mib", r.rss_peak_mib}};
  if (g.preset) j["motion"] = std::string(sim::MotionName(g.preset_def.motion));
  std::optional<double> full_ms;
  for (const Row& row : r.rows) {
    if (!row.peer && row.name == "full") full_ms = Summarise(row).total.median;
  }
  for (const Row& row : r.rows) {
    const Aggregate a = Summarise(row);
    nlohmann::json e{{"name", row.name},
                     {"seeds_ok", a.seeds},
                     {"ape_rmse_m", {{"median", a.ape_rmse_median}, {"min", a.ape_rmse_min}, {"max", a.ape_rmse_max}}},
                     {"ape_max_m", a.ape_max},
                     {"rpe_rmse_median_m", a.rpe_rmse_median},
                     {"worst_frame_m", a.worst_frame_m},
                     {"worst_frame_seed", a.worst_frame_seed},
                     {"worst_frame_index", a.worst_frame_index},
                     {"median_frame_m", a.median_frame_m},
                     {"worst_to_median_frame", a.worst_ratio},
                     {"ms", {{"total", ToJson(a.total)}}}};
    if (a.has_truth) {
      const bench::MovingLabelScore& m = a.moving_labels;
      e["moving_labels"] = {{"precision", m.Precision()},
                            {"recall", m.Recall()},
                            {"static_labelled_moving", m.StaticFlaggedShare()},
                            {"worst_seed", {{"precision", a.worst_precision},
                                            {"recall", a.worst_recall},
                                            {"static_labelled_moving", a.worst_static_flagged}}},
                            {"moving_points", m.moving_found + m.moving_missed},
                            {"static_points", m.static_points},
                            {"unscored_scans", m.mismatched_scans}};
    }
    if (row.peer) {
      e["time_offset_s"] = row.offset_s;
      if (full_ms && a.total.median > 0) e["full_over_peer_ms"] = *full_ms / a.total.median;
    } else {
      e["ms"]["features"] = ToJson(a.features);
      e["ms"]["registration"] = ToJson(a.registration);
      e["ms"]["map_update"] = ToJson(a.map_update);
      e["median_iterations"] = a.iterations_median;
      e["median_searched_points"] = a.searched_points_median;
      if (a.allocations_counted) {
        e["heap_allocations_per_scan"] = ToJson(a.allocations);
        e["heap_allocations_warm_up_scans"] = kAllocationWarmUpScans;
      }
      e["map_points"] = {{"median", a.map_median}, {"max", a.map_max}};
      e["degenerate_share"] = a.degenerate_share;
      e["registered_share"] = a.registered_share;
    }
    for (const SeedResult& s : row.seeds) e["per_seed"].push_back(ToJson(s));
    j[row.peer ? "peers" : "modes"].push_back(e);
  }
  return j;
}

bool WriteJson(const std::string& path, const nlohmann::json& report) {
  const fs::path tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << report.dump(2) << "\n";
    if (!out) return false;
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  return !ec;
}

std::string ListText(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// How a peer is called and evaluated, printed before anything runs.
void PrintPeerSetup(const Peer& p) {
  std::string command = p.path + (p.style == PeerStyle::kAnchor ? " SEQ_DIR OUT.tum"
                                                                 : " SEQ --out poses.tum --timing timing.csv --quiet");
  for (const std::string& a : p.args) command += " " + a;
  std::printf("peer %s: `%s` (%s runner%s; per-scan times from %s); poses at stamp + %s\n", p.name.c_str(),
              command.c_str(), PeerStyleName(p.style), p.style_detected ? ", by its file name" : "",
              p.style == PeerStyle::kAnchor ? "$ANCHOR_TIMES_OUT" : "--timing", PeerOffsetText(p).c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Odometry benchmark: accuracy and per-stage speed of every registration mode (and "
               "optional peer runners) on full-length realistic simulated runs"};
  Options o;
  std::string presets_help;
  for (const sim::Preset& p : sim::Presets()) {
    presets_help += "\n  " + p.name + " (" + std::to_string(p.scans) + " scans): " + p.what;
  }
  app.footer(
      "Presets:" + presets_help +
      "\n\nEach scan is simulated once and given to one pipeline per mode in turn (identical scans, "
      "same machine load); only per-scan results are kept. Rows per (preset, sensor, mode) pool "
      "the seeds: APE RMSE median, max single-pose APE, seed spread (min-max APE RMSE), RPE RMSE "
      "median, the worst frame error (translation error of one scan-to-scan relative pose) and "
      "its ratio to the median frame error, per-stage ms median/p99, iterations, map size (these "
      "pooled over all scans of all seeds), "
      "degenerate share. RSS is the whole process's VmRSS after the last scan, all modes' pipelines "
      "alive (max over seeds), and its peak VmHWM.\n\n"
      "Peers: --peer NAME=[STYLE:]PATH[:ARG,ARG...] runs a peer odometry on the same sequence "
      "written to disk (a temporary directory, or --cache-dir) after the modes. STYLE anchor: "
      "`PATH SEQ_DIR OUT.tum ARGS`, the runners of ../shared/peers (kiss_run, genz_run): per-scan "
      "times from the file named by $ANCHOR_TIMES_OUT, checked against their `[tag] scans=N "
      "per-scan time (ms)` line. STYLE bench: `PATH SEQ --out poses.tum --timing timing.csv --quiet "
      "ARGS`, timing.csv one ms value per scan. Without STYLE a runner named kiss_run or genz_run is "
      "anchor, any other bench. Extra arguments follow a colon, comma separated: "
      "--peer kiss=/tmp/peers/bin/kiss_run --peer genz=/tmp/peers/bin/genz_run:--deskew. "
      "A peer's poses are evaluated at stamp + an offset against the simulator's truth at that time: "
      "kiss_run 1 scan period (it reports the pose at the scan's end, 0.5 with --no-deskew), genz_run "
      "0.5 (mid-scan), others 0; --peer-offset NAME=SECONDS sets it. The offset is in the peer's row. "
      "A peer that gives no result (missing, failing, printing nothing) says why in its row and the "
      "bench exits with 1. On disk a scan takes ~0.7 MB (VLP-16) to ~1.5 MB (OS1-64): a temporary "
      "sequence is removed after its peers ran, --cache-dir keeps them all.\n\n"
      "Legacy: --scenes NAME,... runs the constant-speed scenes with --scans scans (default 100) "
      "and seed --seed (default 1) instead of the presets.");
  auto* presets_opt = app.add_option("--presets", o.presets, "realistic presets, comma separated")
                          ->delimiter(',')->capture_default_str();
  app.add_option("--scenes", o.scenes, "legacy: constant-speed scenes instead of presets")
      ->delimiter(',')->excludes(presets_opt);
  app.add_option("--sensors", o.sensors, "simulated sensors")->delimiter(',')->capture_default_str();
  app.add_option("--modes", o.modes, "registration modes (the first is the timing baseline)")
      ->delimiter(',')->capture_default_str();
  auto* seeds_opt = app.add_option("--seeds", o.seeds, "simulator seeds (presets default: 1,2,3)")
                        ->delimiter(',');
  app.add_option("--seed", o.seed, "single seed (legacy; same as --seeds S)")->excludes(seeds_opt);
  app.add_option("--scans", o.scans,
                 "scans per run (presets: the first N of the walk, default the whole walk; "
                 "scenes: default 100)")
      ->check(CLI::Range(3, 100000));
  app.add_option("--peer", o.peer_specs, "peer runner NAME=[anchor:|bench:]PATH[:ARG,ARG...] (repeatable)");
  app.add_option("--peer-offset", o.peer_offset_specs,
                 "NAME=SECONDS: the peer's poses are evaluated at stamp + SECONDS (repeatable; default "
                 "per runner, see below)");
  app.add_option("--cache-dir", o.cache_dir,
                 "keep simulated sequences here (sequence directory format) and reuse them");
  app.add_option("--json", o.json_path, "write all numbers to this JSON file (after every group)");
  app.add_option("--config", o.config_path, "odometry YAML config (the mode is overridden)");
  app.add_option("--variant", o.variant_specs,
                 "NAME=PATH: one more row, the odometry YAML config at PATH as it is (repeatable), "
                 "e.g. moving=on.yaml beside the modes on the same scans");
  app.add_flag("--no-remap", o.no_remap, "full modes without solution remapping (weights only)");
  app.add_flag("--per-scan", o.per_scan, "print every scan's motion error (debugging)");
  app.add_flag("--quiet", o.quiet, "no progress on stderr");
  CLI11_PARSE(app, argc, argv);
  // Time what dammloamd runs: its allocator thresholds (io/process_memory.hpp).
  dammloam::io::ReturnFreedMemoryEagerly(dammloam::io::kDaemonKeepFreeBytes);

  const bool legacy = !o.scenes.empty();
  const bool seed_given = app.count("--seed") > 0;
  if (o.seeds.empty()) {
    o.seeds = legacy || seed_given ? std::vector<std::uint64_t>{o.seed} : std::vector<std::uint64_t>{1, 2, 3};
  }
  for (const std::string& spec : o.peer_specs) {
    const auto peer = ParsePeer(spec);
    if (!peer) {
      std::fprintf(stderr, "error: --peer '%s': expected NAME=PATH[:ARG,ARG...]\n", spec.c_str());
      return 2;
    }
    if (access(peer->path.c_str(), X_OK) != 0) {
      std::fprintf(stderr, "error: --peer %s: '%s' is not an executable (%s)%s\n", peer->name.c_str(),
                   peer->path.c_str(), std::strerror(errno),
                   peer->style == PeerStyle::kAnchor ? "; ../shared/peers/build.sh builds kiss_run and genz_run" : "");
      return 2;
    }
    o.peers.push_back(*peer);
  }
  for (const std::string& spec : o.peer_offset_specs) {
    if (!ParsePeerOffset(spec, o.peers)) {
      std::fprintf(stderr, "error: --peer-offset '%s': expected NAME=SECONDS with NAME one of the --peer names\n",
                   spec.c_str());
      return 2;
    }
  }

  OdometryConfig base_config;
  try {
    if (!o.config_path.empty()) base_config = io::LoadOdometryConfig(o.config_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  std::vector<OdometryConfig> configs;
  std::vector<std::string> row_names;
  for (const std::string& mode_name : o.modes) {
    const auto mode = ParseRegistrationMode(mode_name);
    if (!mode) {
      std::fprintf(stderr, "error: unknown mode '%s'\n", mode_name.c_str());
      return 2;
    }
    OdometryConfig config = base_config;
    config.registration.mode = *mode;
    if (o.no_remap) config.registration.remap_degenerate_directions = false;
    configs.push_back(config);
    row_names.push_back(mode_name);
  }
  for (const std::string& spec : o.variant_specs) {
    const std::size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
      std::fprintf(stderr, "error: --variant '%s': expected NAME=PATH\n", spec.c_str());
      return 2;
    }
    try {
      configs.push_back(io::LoadOdometryConfig(spec.substr(eq + 1)));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: --variant %s: %s\n", spec.substr(0, eq).c_str(), e.what());
      return 2;
    }
    row_names.push_back(spec.substr(0, eq));
  }
  if (configs.empty()) {
    std::fprintf(stderr, "error: no modes\n");
    return 2;
  }

  std::vector<Group> groups;
  for (const std::string& name : legacy ? o.scenes : o.presets) {
    for (const std::string& sensor_name : o.sensors) {
      Group g;
      g.label = name;
      const auto sensor = sim::MakeSensorSpec(sensor_name);
      if (!sensor) {
        std::fprintf(stderr, "error: unknown sensor '%s' (known: %s)\n", sensor_name.c_str(),
                     ListText(sim::SensorNames()).c_str());
        return 2;
      }
      g.sensor = *sensor;
      if (legacy) {
        const auto scene = sim::ParseSceneKind(name);
        if (!scene) {
          std::fprintf(stderr, "error: unknown scene '%s'\n", name.c_str());
          return 2;
        }
        g.scene = *scene;
        g.scans = o.scans.value_or(100);
      } else {
        const auto preset = sim::FindPreset(name);
        if (!preset) {
          std::fprintf(stderr, "error: unknown preset '%s' (known: %s)\n", name.c_str(),
                       ListText(sim::PresetNames()).c_str());
          return 2;
        }
        g.preset = true;
        g.preset_def = *preset;
        g.scans = std::min(o.scans.value_or(preset->scans), preset->scans);
      }
      groups.push_back(g);
    }
  }

  nlohmann::json report{{"modes", o.modes}, {"seeds", o.seeds}, {"groups", nlohmann::json::array()}};
  for (const Peer& p : o.peers) {
    report["peers"].push_back({{"name", p.name}, {"path", p.path}, {"style", PeerStyleName(p.style)}, {"args", p.args}});
    PrintPeerSetup(p);
  }
  const auto start = std::chrono::steady_clock::now();
  int peer_failures = 0;  // a column without numbers must not pass for a measured one
  for (const Group& g : groups) {
    GroupResult result;
    try {
      result = RunGroup(o, g, configs, row_names);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s / %s: %s\n", g.label.c_str(), g.sensor.name.c_str(), e.what());
      return 1;
    }
    PrintGroup(o, result);
    for (const Row& row : result.rows) {
      for (const SeedResult& seed : row.seeds) peer_failures += row.peer && !seed.failure.empty();
    }
    report["groups"].push_back(ToJson(result, o));
    if (!o.json_path.empty() && !WriteJson(o.json_path, report)) {
      std::fprintf(stderr, "error: cannot write %s\n", o.json_path.c_str());
      return 1;
    }
  }
  std::printf("\nwall time %.0f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (peer_failures > 0) {
    std::fprintf(stderr, "error: %d peer run(s) gave no result (the reasons are in their rows)\n", peer_failures);
    return 1;
  }
  return 0;
}
