// dammloam-command as a separate process against dammloamd fed by dammloam-replay (loopback DDS,
// own domain per test): save_map exits 0 with a map the map store loads, the daemon's errors
// exit 1 with its message (a missing or wrong --token too: refused), no daemon exits 3 within
// the timeout, bad usage and a missing CYCLONEDDS_URI exit 2.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "tests/system/child_process.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/system/sim_sequence.hpp"
#include "io/mapstore/map_store.hpp"

namespace dammloam::test {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
constexpr int kScans = 12;              // enough for keyframes in the back-end's map
constexpr const char* kTimeout = "60";  // the tool's --timeout: sanitizer builds are slow
constexpr milliseconds kToolWait(70000);
constexpr const char* kToken = "tool-test-token";

class CommandTool : public ::testing::Test {
 protected:
  void SetUp() override {
    UseLoopbackDds();
    for (const char* tool : {"dammloamd", "dammloam-replay", "dammloam-command"}) {
      if (!ToolExists(tool)) GTEST_SKIP() << tool << " not built in " << DAMMLOAM_BIN_DIR;
    }
  }
};

struct CommandRun {
  std::optional<int> code;  // nullopt: still running after kToolWait
  std::string output;
};

// Commands enabled inside dir, with a token.
fs::path WriteCommandConfig(const fs::path& dir) {
  std::ofstream(dir / "daemon.yaml") << "dammloamd:\n  commands:\n    enabled: true\n"
                                     << "    map_root: " << dir.string() << "\n"
                                     << "    token: " << kToken << "\n";
  return dir / "daemon.yaml";
}

// dammloamd (with the back-end: it holds the map save_map writes) after a lock-step replay of
// a short simulated drive written to dir/seq.
class TrackingDaemon {
 public:
  TrackingDaemon(std::uint32_t domain, const fs::path& dir)
      : domain_(domain),
        daemon_("dammloamd",
                {"--domain", std::to_string(domain), "--sensor-meta",
                 (dir / "seq" / "meta.json").string(), "--config",
                 WriteCommandConfig(dir).string()},
                dir / "daemon.log") {
    ChildProcess replay("dammloam-replay",
                        {(dir / "seq").string(), "--domain", std::to_string(domain), "--lockstep",
                         "--lockstep-timeout", "60", "--wait-subscriber", "30"},
                        dir / "replay.log");
    const auto code = replay.Wait(milliseconds(300000));
    EXPECT_TRUE(code && *code == 0) << replay.Log() << daemon_.Log();
  }

  // Runs dammloam-command with these arguments on this daemon's domain (and its token).
  CommandRun Command(const std::vector<std::string>& args, const fs::path& log,
                     const std::string& token = kToken) const {
    std::vector<std::string> all = args;
    all.insert(all.end(), {"--domain", std::to_string(domain_), "--timeout", kTimeout});
    if (!token.empty()) all.insert(all.end(), {"--token", token});
    ChildProcess tool("dammloam-command", all, log);
    const std::optional<int> code = tool.Wait(kToolWait);
    return {code, tool.Log()};
  }

  std::string Log() const { return daemon_.Log(); }

 private:
  std::uint32_t domain_;
  ChildProcess daemon_;
};

// The sequence the daemons are fed with, in dir/seq.
void WriteShortSequence(const fs::path& dir) {
  WriteSequence(SmallSimulator(kScans), kScans, dir / "seq");
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_F(CommandTool, SaveMapExitsZeroAndTheMapStoreLoadsTheDirectory) {
  const test::TempDir dir("system-tool-save");
  WriteShortSequence(dir.path());
  const TrackingDaemon daemon(101, dir.path());
  const CommandRun run = daemon.Command({"save_map", (dir / "map").string()}, dir / "command.log");
  ASSERT_TRUE(run.code) << "dammloam-command still running\n" << run.output;
  EXPECT_EQ(*run.code, 0) << run.output << daemon.Log();
  EXPECT_TRUE(Contains(run.output, "ok: ")) << run.output;
  EXPECT_TRUE(Contains(run.output, (dir / "map").string())) << run.output;

  const backend::MapData map = mapstore::LoadMap(dir / "map");
  EXPECT_GE(map.keyframes.size(), 1u);
  EXPECT_GT(map.global_points.size(), 0u);
  EXPECT_EQ(map.global_labels.size(), map.global_points.size());
}

TEST_F(CommandTool, DaemonErrorsExitOneWithTheDaemonsMessage) {
  const test::TempDir dir("system-tool-errors");
  WriteShortSequence(dir.path());
  const TrackingDaemon daemon(102, dir.path());
  // A regular file as the target: the daemon refuses to replace it.
  std::ofstream(dir / "precious.txt") << "not a map\n";
  CommandRun run = daemon.Command({"save_map", (dir / "precious.txt").string()},
                                  dir / "bad-target.log");
  ASSERT_TRUE(run.code) << run.output;
  EXPECT_EQ(*run.code, 1) << run.output;
  EXPECT_TRUE(Contains(run.output, "error: ")) << run.output;
  EXPECT_TRUE(Contains(run.output, "precious.txt")) << run.output;
  std::string kept;
  std::getline(std::ifstream(dir / "precious.txt"), kept);
  EXPECT_EQ(kept, "not a map");

  // The earlier (latched) error reply must not be taken for this request's.
  run = daemon.Command({"fly_to_the_moon", "now"}, dir / "unknown.log");
  ASSERT_TRUE(run.code) << run.output;
  EXPECT_EQ(*run.code, 1) << run.output;
  EXPECT_TRUE(Contains(run.output, "unknown command 'fly_to_the_moon'")) << run.output;
  EXPECT_FALSE(Contains(run.output, "precious.txt")) << run.output;

  // Without the token, and with a wrong one: refused, nothing written.
  run = daemon.Command({"save_map", (dir / "map").string()}, dir / "no-token.log", "");
  ASSERT_TRUE(run.code) << run.output;
  EXPECT_EQ(*run.code, 1) << run.output;
  EXPECT_TRUE(Contains(run.output, "error: refused [wrong_token]")) << run.output;
  run = daemon.Command({"save_map", (dir / "map").string()}, dir / "bad-token.log", "guess");
  ASSERT_TRUE(run.code) << run.output;
  EXPECT_EQ(*run.code, 1) << run.output;
  EXPECT_TRUE(Contains(run.output, "error: refused [wrong_token]")) << run.output;
  EXPECT_FALSE(fs::exists(dir / "map"));
}

TEST_F(CommandTool, WithoutADaemonExitsThreeWithinTheTimeout) {
  const test::TempDir dir("system-tool-no-daemon");
  const auto t0 = std::chrono::steady_clock::now();
  ChildProcess tool("dammloam-command",
                    {"save_map", (dir / "map").string(), "--domain", "103", "--timeout", "2"},
                    dir / "command.log");
  const std::optional<int> code = tool.Wait(milliseconds(10000));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("no daemon: dammloam-command --timeout 2 exited after %.3f s\n", seconds);
  ASSERT_TRUE(code) << tool.Log();
  EXPECT_EQ(*code, 3) << tool.Log();
  EXPECT_LT(seconds, 3.0);
  EXPECT_TRUE(Contains(tool.Log(), "no dammloamd")) << tool.Log();
  EXPECT_FALSE(fs::exists(dir / "map"));
}

TEST_F(CommandTool, BadUsageAndAMissingCycloneDdsUriExitTwo) {
  const test::TempDir dir("system-tool-usage");
  ChildProcess no_name("dammloam-command", {"--domain", "104"}, dir / "no-name.log");
  ChildProcess bad_timeout("dammloam-command", {"save_map", "x", "--timeout", "-1"},
                           dir / "bad-timeout.log");
  const std::string saved = std::getenv("CYCLONEDDS_URI");
  unsetenv("CYCLONEDDS_URI");
  ChildProcess no_uri("dammloam-command", {"save_map", "x", "--domain", "104"}, dir / "no-uri.log");
  setenv("CYCLONEDDS_URI", saved.c_str(), 1);
  for (ChildProcess* p : {&no_name, &bad_timeout, &no_uri}) {
    const auto code = p->Wait(milliseconds(10000));
    ASSERT_TRUE(code) << p->Log();
    EXPECT_EQ(*code, 2) << p->Log();
  }
  EXPECT_TRUE(Contains(no_uri.Log(), "CYCLONEDDS_URI is not set")) << no_uri.Log();
  EXPECT_TRUE(Contains(no_uri.Log(), "--allow-default-network")) << no_uri.Log();
}

}  // namespace
}  // namespace dammloam::test
