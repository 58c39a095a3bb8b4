// Crash safety of SaveMap: a child process saves maps in a loop and is SIGKILLed at random
// points; the map directory must then load and hold exactly the last completed save or the one
// in flight. Also: disk-full and permission errors name the path and keep the old map.
#include <gtest/gtest.h>
#include <signal.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <utility>

#include "core/backend/scan_context.hpp"
#include "core/geometry/se3.hpp"
#include "io/mapstore/map_store.hpp"
#include "tests/support/temp_dir.hpp"

namespace dammloam::mapstore {
namespace {

namespace fs = std::filesystem;
using backend::MapData;

// Keyframe k of generation g has scan_index 100 g + k: the loaded map names its generation.
constexpr std::uint64_t kScanIndexPerGeneration = 100;

Eigen::Isometry3d RandomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << u(rng), u(rng), 0.1 * u(rng);
  T.linear() = Eigen::AngleAxisd(0.1 * u(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

// Float-representable coordinates: the store keeps points as float32, so they round-trip exactly.
std::vector<Eigen::Vector3d> RandomPoints(std::mt19937& rng, std::size_t count) {
  std::uniform_real_distribution<float> u(-30.0f, 30.0f);
  std::vector<Eigen::Vector3d> points(count);
  for (Eigen::Vector3d& p : points) p = Eigen::Vector3f(u(rng), u(rng), u(rng)).cast<double>();
  return points;
}

std::vector<PointClass> CyclingLabels(std::size_t count, std::uint64_t offset) {
  std::vector<PointClass> labels(count);
  for (std::size_t i = 0; i < count; ++i) {
    labels[i] = static_cast<PointClass>((i + offset) % kNumPointClasses);
  }
  return labels;
}

// Generation g's map (~0.7 MB on disk): counts and contents depend on g, so files mixed from
// two generations would also fail the loader's own checks.
MapData GenerationMap(std::uint64_t generation) {
  std::mt19937 rng(static_cast<std::uint32_t>(generation) + 1);
  MapData map;
  const auto num_keyframes = static_cast<std::uint32_t>(2 + generation % 3);
  for (std::uint32_t k = 0; k < num_keyframes; ++k) {
    backend::Keyframe kf;
    kf.id = k;
    kf.scan_index = kScanIndexPerGeneration * generation + k;
    kf.stamp = static_cast<double>(generation) + 0.1 * k;
    kf.T_world_sensor_odom = RandomPose(rng);
    kf.T_world_sensor = RandomPose(rng);
    kf.edge_covariance = Eigen::Matrix<double, 6, 6>::Identity() * (1.0 + generation);
    kf.points = RandomPoints(rng, 4000 + 500 * (generation % 2));
    kf.labels = CyclingLabels(kf.points.size(), generation + k);
    kf.descriptor = backend::MakeScanContext(kf.points, map.scan_context);
    map.keyframes.push_back(std::move(kf));
  }
  map.loops.push_back({0, num_keyframes - 1, RandomPose(rng)});
  map.global_points = RandomPoints(rng, 30000 + 7 * (generation % 5));
  map.global_labels = CyclingLabels(map.global_points.size(), generation);
  return map;
}

std::uint64_t GenerationOf(const MapData& map) {
  return map.keyframes.empty() ? 0 : map.keyframes[0].scan_index / kScanIndexPerGeneration;
}

bool SamePose(const Eigen::Isometry3d& loaded, const Eigen::Isometry3d& saved) {
  return loaded.matrix() == Normalized(saved).matrix();  // the loader re-orthonormalizes
}

// "" when `loaded` is exactly `saved` after one round trip, else the first difference.
std::string KeyframeDifference(const backend::Keyframe& a, const backend::Keyframe& b) {
  const std::string k = "keyframe " + std::to_string(b.id) + ": ";
  if (a.id != b.id || a.scan_index != b.scan_index || a.stamp != b.stamp) return k + "header";
  if (!SamePose(a.T_world_sensor_odom, b.T_world_sensor_odom)) return k + "odometry pose";
  if (!SamePose(a.T_world_sensor, b.T_world_sensor)) return k + "corrected pose";
  if (a.edge_covariance != b.edge_covariance) return k + "covariance";
  if (a.points != b.points) return k + "points";
  if (a.labels != b.labels) return k + "labels";
  if (a.descriptor.grid != b.descriptor.grid) return k + "descriptor";
  if (a.descriptor.ring_key != b.descriptor.ring_key) return k + "ring key";
  return "";
}

std::string MapDifference(const MapData& loaded, const MapData& saved) {
  if (loaded.keyframes.size() != saved.keyframes.size()) return "keyframe count";
  for (std::size_t k = 0; k < saved.keyframes.size(); ++k) {
    const std::string diff = KeyframeDifference(loaded.keyframes[k], saved.keyframes[k]);
    if (!diff.empty()) return diff;
  }
  if (loaded.loops.size() != saved.loops.size()) return "loop count";
  for (std::size_t i = 0; i < saved.loops.size(); ++i) {
    const auto& a = loaded.loops[i];
    const auto& b = saved.loops[i];
    if (a.from != b.from || a.to != b.to || !SamePose(a.T_from_to, b.T_from_to)) return "loop";
  }
  if (loaded.global_points != saved.global_points) return "global points";
  if (loaded.global_labels != saved.global_labels) return "global labels";
  const auto& sa = loaded.scan_context;
  const auto& sb = saved.scan_context;
  if (sa.rings != sb.rings || sa.sectors != sb.sectors || sa.max_range != sb.max_range ||
      sa.sensor_height != sb.sensor_height) {
    return "scan context";
  }
  return "";
}

std::vector<std::string> EntriesOf(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::uint64_t EnvOr(const char* name, std::uint64_t fallback) {
  const char* value = std::getenv(name);
  return value && *value ? std::strtoull(value, nullptr, 10) : fallback;
}

// The child: saves generations first, first + 1, ... until killed, writing one byte to
// `done_fd` after each completed save. Exit codes other than the SIGKILL are failures.
[[noreturn]] void SaveForever(const fs::path& dir, std::uint64_t first, int done_fd) {
  for (std::uint64_t generation = first;; ++generation) {
    try {
      SaveMap(dir, GenerationMap(generation));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "child save failed: %s\n", e.what());
      ::_exit(3);
    }
    const char byte = 1;
    if (::write(done_fd, &byte, 1) != 1) ::_exit(4);
  }
}

// A forked child running `body(write_fd)`, which must not return; the parent keeps the read end
// of the pipe to hear from it.
struct Child {
  pid_t pid;
  int read_fd;
};
template <typename Body>
Child ForkWithPipe(Body body) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::close(pipe_fds[0]);
    body(pipe_fds[1]);
    ::_exit(0);
  }
  ::close(pipe_fds[1]);
  return {pid, pipe_fds[0]};
}

// Everything the child wrote (read to end of file, then closed) and its wait status.
std::pair<std::string, int> CollectChild(const Child& child) {
  std::string bytes;
  char buffer[512];
  for (ssize_t n; (n = ::read(child.read_fd, buffer, sizeof buffer)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) ADD_FAILURE() << "read from the child: " << std::strerror(errno);
    if (n < 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(child.read_fd);
  int status = 0;
  while (::waitpid(child.pid, &status, 0) < 0 && errno == EINTR) {
  }
  return {bytes, status};
}

struct KillOutcome {
  std::size_t completed_saves = 0;
  bool killed = false;  // false: the child exited on its own (a failed save)
};

// Forks a saver, SIGKILLs it after `delay`, and reaps it.
KillOutcome RunAndKill(const fs::path& dir, std::uint64_t first, std::chrono::microseconds delay) {
  const Child child = ForkWithPipe([&](int done_fd) { SaveForever(dir, first, done_fd); });
  std::this_thread::sleep_for(delay);
  ::kill(child.pid, SIGKILL);
  const auto [bytes, status] = CollectChild(child);
  KillOutcome outcome;
  outcome.completed_saves = bytes.size();
  outcome.killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  return outcome;
}

std::chrono::microseconds TimeOneSave(const fs::path& dir, std::uint64_t generation) {
  const auto start = std::chrono::steady_clock::now();
  SaveMap(dir, GenerationMap(generation));
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() -
                                                               start);
}

// After a kill: `dir` must load and be exactly generation `last_done` (the last completed save)
// or `last_done` + 1 (the save in flight), and the load must clear the killed save's staging
// directory. Returns the generation found, nullopt (with the failure recorded) otherwise.
std::optional<std::uint64_t> CheckMapAfterKill(const fs::path& dir, std::uint64_t last_done) {
  MapData loaded;
  try {
    loaded = LoadMap(dir);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "no loadable map: " << e.what();
    return std::nullopt;
  }
  const std::uint64_t found = GenerationOf(loaded);
  if (found != last_done && found != last_done + 1) {
    ADD_FAILURE() << "generation " << found << ", expected " << last_done
                  << " (last completed save) or " << last_done + 1 << " (in flight)";
    return std::nullopt;
  }
  const std::string difference = MapDifference(loaded, GenerationMap(found));
  if (!difference.empty()) {
    ADD_FAILURE() << "generation " << found << " differs from what was saved: " << difference;
    return std::nullopt;
  }
  if (EntriesOf(dir.parent_path()) != std::vector<std::string>{"map"}) {
    ADD_FAILURE() << "the load left a staging directory behind";
    return std::nullopt;
  }
  return found;
}

TEST(MapStoreCrash, SigkillDuringSavesAlwaysLeavesTheOldOrTheNewMap) {
  const std::uint64_t seed = EnvOr("DAMMLOAM_CRASH_SEED", 16);
  const std::uint64_t iterations = EnvOr("DAMMLOAM_CRASH_ITERATIONS", 120);
  const test::TempDir tmp;
  const fs::path dir = tmp / "map";
  SaveMap(dir, GenerationMap(0));
  const std::chrono::microseconds save_time = TimeOneSave(dir, 0);
  std::mt19937_64 rng(seed);
  // Up to three saves' time: kills land in every phase of a save, and between saves.
  std::uniform_int_distribution<std::int64_t> delay_us(0, 3 * save_time.count() + 1000);
  std::uint64_t generation = 0;
  std::size_t mid_save = 0;           // kills that left a staging directory
  std::size_t in_flight_visible = 0;  // kills after the swap, before the save returned
  for (std::uint64_t i = 0; i < iterations; ++i) {
    const KillOutcome outcome =
        RunAndKill(dir, generation + 1, std::chrono::microseconds(delay_us(rng)));
    ASSERT_TRUE(outcome.killed) << "iteration " << i << ": the child ended on its own";
    mid_save += EntriesOf(tmp.path()).size() > 1 ? 1 : 0;
    const std::uint64_t last_done = generation + outcome.completed_saves;
    const std::optional<std::uint64_t> found = CheckMapAfterKill(dir, last_done);
    ASSERT_TRUE(found) << "iteration " << i << " (seed " << seed << ")";
    in_flight_visible += *found == last_done + 1 ? 1 : 0;
    generation = *found;
  }
  std::printf("seed %llu: %llu kills (save %.1f ms), %zu mid-save, %zu with the interrupted "
              "save already visible, %llu generations, all loadable and exact\n",
              static_cast<unsigned long long>(seed), static_cast<unsigned long long>(iterations),
              static_cast<double>(save_time.count()) / 1000.0, mid_save, in_flight_visible,
              static_cast<unsigned long long>(generation));
  // The test must have hit saves in progress, or it proves nothing.
  EXPECT_GT(mid_save, iterations / 10);
}

// What a child process reported: its exit code and the IoError message it sent, if any.
struct ChildReport {
  int exit_code = -1;
  std::optional<std::string> error;
};
constexpr int kNoIoError = 1;
constexpr int kSetupUnavailable = 5;  // the child could not set up the condition: skip

// Runs `save` in a child process (whose limits, identity and mounts the test may change) and
// reports the IoError it threw. `after_error` runs in the child after the error and returns
// the exit code (0: the state left behind is right).
template <typename Save, typename AfterError>
ChildReport SaveInChild(Save save, AfterError after_error) {
  const Child child = ForkWithPipe([&](int message_fd) {
    try {
      save();
    } catch (const io::IoError& e) {
      const std::string message = e.what();
      const bool sent = ::write(message_fd, message.data(), message.size()) ==
                        static_cast<ssize_t>(message.size());
      ::_exit(sent ? after_error() : 2);
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(kNoIoError);
  });
  const auto [message, status] = CollectChild(child);
  ChildReport report;
  report.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (!message.empty()) report.error = message;
  return report;
}

// Exit code for the child: 0 when `dir` still holds generation 0 exactly and nothing else is
// left next to it.
int OldMapIntact(const fs::path& dir) {
  try {
    const bool exact = MapDifference(LoadMap(dir), GenerationMap(0)).empty();
    const bool alone = EntriesOf(dir.parent_path()) == std::vector<std::string>{"map"};
    return exact && alone ? 0 : 8;
  } catch (...) {
    return 9;
  }
}

std::uintmax_t DirectoryBytes(const fs::path& dir) {
  std::uintmax_t bytes = 0;
  for (const auto& entry : fs::directory_iterator(dir)) bytes += entry.file_size();
  return bytes;
}

TEST(MapStoreErrors, DiskFullNamesTheFileAndKeepsTheOldMap) {
  const test::TempDir tmp;
  const fs::path reference = tmp / "reference";
  SaveMap(reference, GenerationMap(0));
  // Room for generation 0 and 64 KiB: generation 1's keyframes.bin (~190 KB) hits ENOSPC.
  const std::uintmax_t size = (DirectoryBytes(reference) / 4096 + 1) * 4096 + 64 * 1024;
  const fs::path small_disk = tmp / "small";
  fs::create_directory(small_disk);
  const fs::path dir = small_disk / "map";
  // The tmpfs lives in the child's own mount namespace and vanishes with it.
  const ChildReport report = SaveInChild(
      [&] {
        const std::string options = "size=" + std::to_string(size);
        if (::unshare(CLONE_NEWNS) != 0 ||
            ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
            ::mount("tmpfs", small_disk.c_str(), "tmpfs", 0, options.c_str()) != 0) {
          ::_exit(kSetupUnavailable);
        }
        SaveMap(dir, GenerationMap(0));
        SaveMap(dir, GenerationMap(1));
      },
      [&] { return OldMapIntact(dir); });
  if (report.exit_code == kSetupUnavailable) {
    GTEST_SKIP() << "cannot mount a small tmpfs here (needs CAP_SYS_ADMIN)";
  }
  ASSERT_TRUE(report.error) << "the save did not report an IoError, exit " << report.exit_code;
  EXPECT_NE(report.error->find(dir.string() + ".tmp-"), std::string::npos) << *report.error;
  EXPECT_NE(report.error->find("keyframes.bin: cannot write: No space left on device"),
            std::string::npos)
      << *report.error;
  EXPECT_EQ(report.exit_code, 0) << "the old map was not intact after the failed save";
}

// Unprivileged stand-in for a full disk: a file size limit makes write() fail part-way.
TEST(MapStoreErrors, FileSizeLimitNamesTheFileAndKeepsTheOldMap) {
  const test::TempDir tmp;
  const fs::path dir = tmp / "map";
  SaveMap(dir, GenerationMap(0));
  const ChildReport report = SaveInChild(
      [&] {
        const rlimit limit{64 * 1024, 64 * 1024};
        ::signal(SIGXFSZ, SIG_IGN);
        if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(kSetupUnavailable);
        SaveMap(dir, GenerationMap(1));
      },
      [] { return 0; });
  ASSERT_TRUE(report.error) << "the save did not report an IoError, exit " << report.exit_code;
  EXPECT_NE(report.error->find(dir.string() + ".tmp-"), std::string::npos) << *report.error;
  EXPECT_NE(report.error->find("keyframes.bin: cannot write: File too large"), std::string::npos)
      << *report.error;
  EXPECT_EQ(EntriesOf(tmp.path()), std::vector<std::string>{"map"}) << "staging left behind";
  EXPECT_EQ(MapDifference(LoadMap(dir), GenerationMap(0)), "");
}

TEST(MapStoreErrors, PermissionDeniedNamesTheDirectory) {
  const test::TempDir tmp;
  const fs::path locked = tmp / "locked";
  fs::create_directory(locked);
  ASSERT_EQ(::chmod(tmp.path().c_str(), 0755), 0);
  ASSERT_EQ(::chmod(locked.c_str(), 0555), 0);
  const ChildReport report = SaveInChild(
      [&] {
        // root ignores permission bits: save as nobody.
        if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) {
          ::_exit(kSetupUnavailable);
        }
        SaveMap(locked / "map", GenerationMap(0));
      },
      [] { return 0; });
  ::chmod(locked.c_str(), 0755);
  ASSERT_TRUE(report.error) << "the save did not report an IoError, exit " << report.exit_code;
  EXPECT_NE(report.error->find(locked.string() + ": cannot create a staging directory for map: "
                                                 "Permission denied"),
            std::string::npos)
      << *report.error;
  EXPECT_TRUE(fs::is_empty(locked));
}

// A staging directory of a live process (another save in progress) is never removed by a load;
// one of a dead process is.
TEST(MapStoreCrash, LoadRemovesOnlyTheLeftOversOfDeadProcesses) {
  const test::TempDir tmp;
  const fs::path dir = tmp / "map";
  SaveMap(dir, GenerationMap(0));
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ASSERT_GT(dead, 0);
  ASSERT_EQ(::waitpid(dead, nullptr, 0), dead);
  const fs::path live_staging = tmp / ("map.tmp-" + std::to_string(::getpid()) + "-abcdef");
  const fs::path dead_staging = tmp / ("map.tmp-" + std::to_string(dead) + "-abcdef");
  const fs::path legacy_aside = tmp / ("map.old-" + std::to_string(dead) + "-12345");
  const fs::path unrelated = tmp / "map.tmp-notes";
  for (const fs::path& p : {live_staging, dead_staging, legacy_aside, unrelated}) {
    fs::create_directory(p);
  }
  EXPECT_EQ(MapDifference(LoadMap(dir), GenerationMap(0)), "");
  EXPECT_TRUE(fs::exists(live_staging));
  EXPECT_FALSE(fs::exists(dead_staging));
  EXPECT_FALSE(fs::exists(legacy_aside));
  EXPECT_TRUE(fs::exists(unrelated));
}

}  // namespace
}  // namespace dammloam::mapstore
