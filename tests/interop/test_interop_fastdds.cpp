// dammloamd (Cyclone DDS) driven by an eProsima Fast DDS client (dammloam-interop-fastdds), both
// pinned to loopback: every pose must arrive, and the trajectory must equal the one of a
// Cyclone-only run (dammloam-replay in lock-step, dammloam-record) of the same scans.
//   NativeTypes: dammloam::msg::PointCloud / Odometry on dammloam_points / dammloam_odometry.
//   Ros2Types:   dammloamd --ros2, sensor_msgs PointCloud2 (ouster-ros layout) on rt/points and
//                nav_msgs Odometry on rt/dammloam/odometry.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "io/sequence_io.hpp"
#include "io/tum.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/system/child_process.hpp"

namespace dammloam::test {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

constexpr int kScans = 40;

// Pins Cyclone DDS to loopback for the processes this test starts (the Fast DDS client pins
// itself in code).
void UseLoopbackDds() {
  const char* uri = std::getenv("CYCLONEDDS_URI");
  if (uri == nullptr || *uri == '\0') {
    const std::string file = std::string("file://") + DAMMLOAM_SOURCE_DIR +
                             "/deploy/cyclonedds-loopback.xml";
    setenv("CYCLONEDDS_URI", file.c_str(), 1);
  }
}

// ChildProcess starts tools from build/bin; the client lives in build/tests.
std::string ClientTool() {
  return fs::relative(DAMMLOAM_INTEROP_CLIENT, DAMMLOAM_BIN_DIR).string();
}

std::vector<std::string> DaemonArgs(std::uint32_t domain, const fs::path& seq, bool ros2) {
  std::vector<std::string> args = {"--domain", std::to_string(domain), "--sensor-meta",
                                   (seq / "meta.json").string(), "--no-loop-closure"};
  if (ros2) args.push_back("--ros2");
  return args;
}

std::string Logs(std::initializer_list<const ChildProcess*> processes) {
  std::string text;
  for (const ChildProcess* p : processes) text += p->Log() + "\n----\n";
  return text;
}

// Stops the daemon with SIGTERM and expects a clean exit.
void StopDaemon(ChildProcess& daemon) {
  daemon.Signal(SIGTERM);
  const auto code = daemon.Wait(milliseconds(10000));
  ASSERT_TRUE(code) << "dammloamd did not stop\n" << daemon.Log();
  EXPECT_EQ(*code, 0) << daemon.Log();
}

// The reference: dammloamd fed by dammloam-replay (lock-step), poses recorded by
// dammloam-record; Cyclone DDS on every end.
std::vector<io::StampedPose> CycloneRun(std::uint32_t domain, const fs::path& seq,
                                        const fs::path& dir) {
  const fs::path tum = dir / "cyclone.tum";
  ChildProcess daemon("dammloamd", DaemonArgs(domain, seq, false), dir / "cyclone-daemon.log");
  ChildProcess record("dammloam-record",
                      {"--domain", std::to_string(domain), "--poses", tum.string(), "--count",
                       std::to_string(kScans), "--timeout", "120"},
                      dir / "cyclone-record.log");
  // --no-imu, --no-wheel: the simulated sequence has an imu.csv and a wheel.csv, which the Fast
  // DDS client does not send (dammloamd would otherwise use them in this run only).
  ChildProcess replay("dammloam-replay",
                      {seq.string(), "--domain", std::to_string(domain), "--lockstep",
                       "--lockstep-timeout", "60", "--wait-subscriber", "30", "--no-imu",
                       "--no-wheel"},
                      dir / "cyclone-replay.log");
  const auto replay_code = replay.Wait(milliseconds(300000));
  EXPECT_TRUE(replay_code && *replay_code == 0) << Logs({&replay, &daemon});
  const auto record_code = record.Wait(milliseconds(60000));
  EXPECT_TRUE(record_code && *record_code == 0) << record.Log();
  StopDaemon(daemon);
  if (!fs::exists(tum)) return {};
  return io::ReadTum(tum);
}

// dammloamd driven by the Fast DDS client.
std::vector<io::StampedPose> FastDdsRun(std::uint32_t domain, const fs::path& seq,
                                        const fs::path& dir, bool ros2, std::string* client_log) {
  const std::string mode = ros2 ? "ros2" : "native";
  const fs::path tum = dir / ("fastdds-" + mode + ".tum");
  ChildProcess daemon("dammloamd", DaemonArgs(domain, seq, ros2),
                      dir / ("fastdds-" + mode + "-daemon.log"));
  ChildProcess client(ClientTool(),
                      {seq.string(), "--mode", mode, "--domain", std::to_string(domain), "--out",
                       tum.string(), "--wait-daemon", "30", "--pose-timeout", "60"},
                      dir / ("fastdds-" + mode + "-client.log"));
  EXPECT_TRUE(client.started());
  const auto code = client.Wait(milliseconds(300000));
  EXPECT_TRUE(code) << "the Fast DDS client did not finish\n" << Logs({&client, &daemon});
  EXPECT_EQ(code.value_or(-1), 0) << Logs({&client, &daemon});
  *client_log = client.Log();
  StopDaemon(daemon);
  if (!fs::exists(tum)) return {};
  return io::ReadTum(tum);
}

// Equal to 1e-9: the daemon sees bit-identical scans in both runs and is deterministic.
void ExpectSameTrajectory(const std::vector<io::StampedPose>& fastdds,
                          const std::vector<io::StampedPose>& cyclone) {
  ASSERT_EQ(cyclone.size(), static_cast<std::size_t>(kScans)) << "Cyclone reference incomplete";
  ASSERT_EQ(fastdds.size(), static_cast<std::size_t>(kScans)) << "Fast DDS run incomplete";
  double max_dt = 0.0, max_dp = 0.0, max_dr = 0.0;
  for (std::size_t i = 0; i < fastdds.size(); ++i) {
    const double dt = std::abs(fastdds[i].t - cyclone[i].t);
    const double dp = (fastdds[i].T.translation() - cyclone[i].T.translation()).norm();
    const double dr = std::abs(
        Eigen::AngleAxisd(fastdds[i].T.rotation().transpose() * cyclone[i].T.rotation()).angle());
    EXPECT_LE(dt, 1e-9) << "scan " << i;
    EXPECT_LE(dp, 1e-9) << "scan " << i;
    EXPECT_LE(dr, 1e-9) << "scan " << i;
    max_dt = std::max(max_dt, dt);
    max_dp = std::max(max_dp, dp);
    max_dr = std::max(max_dr, dr);
  }
  std::cout << "max difference Fast DDS vs Cyclone run: time " << max_dt << " s, position "
            << max_dp << " m, rotation " << max_dr << " rad" << std::endl;
}

class FastDdsInterop : public ::testing::Test {
 protected:
  void SetUp() override {
    UseLoopbackDds();
    for (const char* tool : {"dammloamd", "dammloam-replay", "dammloam-record", "dammloam-simulate"}) {
      if (!ToolExists(tool)) GTEST_SKIP() << tool << " not built in " << DAMMLOAM_BIN_DIR;
    }
    ASSERT_TRUE(fs::exists(DAMMLOAM_INTEROP_CLIENT)) << DAMMLOAM_INTEROP_CLIENT;
  }

  // ~40 scans of a small simulated VLP-16 sequence.
  fs::path Simulate(const fs::path& dir) {
    const fs::path seq = dir / "seq";
    ChildProcess simulate("dammloam-simulate",
                          {"--preset", "wheeled-zigzag", "--sensor", "vlp-16", "--columns", "900",
                           "--scans", std::to_string(kScans), "--seed", "7", "--out",
                           seq.string(), "--overwrite"},
                          dir / "simulate.log");
    const auto code = simulate.Wait(milliseconds(120000));
    EXPECT_TRUE(code && *code == 0) << simulate.Log();
    return seq;
  }
};

TEST_F(FastDdsInterop, NativeTypesFastDdsClientMatchesCycloneRun) {
  const test::TempDir tmp("interop-native");
  const fs::path& dir = tmp.path();
  const fs::path seq = Simulate(dir);
  ASSERT_FALSE(HasFailure());
  const auto cyclone = CycloneRun(141, seq, dir);
  ASSERT_FALSE(HasFailure());
  std::string client_log;
  const auto fastdds = FastDdsRun(142, seq, dir, /*ros2=*/false, &client_log);
  ASSERT_FALSE(HasFailure()) << client_log;
  EXPECT_NE(client_log.find("received " + std::to_string(kScans) + " of " +
                            std::to_string(kScans) + " poses"),
            std::string::npos)
      << client_log;
  ExpectSameTrajectory(fastdds, cyclone);
}

// The ouster-ros layout carries point times as uint32 nanoseconds, the replay tool's as float32
// seconds. The Cyclone reference and the Fast DDS client therefore both read a copy of the
// sequence whose point times are already what survives the trip through nanoseconds (what the
// daemon reads back: float(ns * 1e-9)), so that the daemon sees bit-identical scans in both runs.
void WriteNanosecondTimeSequence(const fs::path& in, const fs::path& out) {
  const io::SequenceReader reader = io::SequenceReader::Open(in);
  io::SequenceWriter writer(out, reader.meta(), /*overwrite=*/true);
  for (std::size_t i = 0; i < reader.size(); ++i) {
    Scan scan = reader.ReadScan(i);
    for (float& t : scan.times) {
      const auto ns = static_cast<std::uint32_t>(std::llround(static_cast<double>(t) * 1e9));
      t = static_cast<float>(ns * 1e-9);
    }
    writer.Write(scan);
  }
}

TEST_F(FastDdsInterop, Ros2TypesFastDdsClientMatchesCycloneRun) {
  const test::TempDir tmp("interop-ros2");
  const fs::path& dir = tmp.path();
  {
    // dammloamd --ros2 comes with the daemon's ROS 2 mode; skip until the daemon has it.
    ChildProcess probe("dammloamd", {"--ros2", "--check-config"}, dir / "probe.log");
    const auto code = probe.Wait(milliseconds(20000));
    ASSERT_TRUE(code) << probe.Log();
    if (*code != 0 && probe.Log().find("--ros2") != std::string::npos) {
      GTEST_SKIP() << "dammloamd does not accept --ros2 yet:\n" << probe.Log();
    }
    ASSERT_EQ(*code, 0) << "dammloamd --ros2 --check-config failed\n" << probe.Log();
  }
  const fs::path seq = Simulate(dir);
  ASSERT_FALSE(HasFailure());
  const fs::path seq_ns = dir / "seq-ns";
  WriteNanosecondTimeSequence(seq, seq_ns);
  const auto cyclone = CycloneRun(143, seq_ns, dir);
  ASSERT_FALSE(HasFailure());
  std::string client_log;
  const auto fastdds = FastDdsRun(144, seq_ns, dir, /*ros2=*/true, &client_log);
  ASSERT_FALSE(HasFailure()) << client_log;
  EXPECT_NE(client_log.find("received " + std::to_string(kScans) + " of " +
                            std::to_string(kScans) + " poses"),
            std::string::npos)
      << client_log;
  EXPECT_NE(client_log.find("time quantization: 0 point times"), std::string::npos) << client_log;
  ExpectSameTrajectory(fastdds, cyclone);
}

}  // namespace
}  // namespace dammloam::test
