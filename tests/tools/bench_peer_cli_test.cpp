// Runs the built dammloam-bench-odometry with stand-in peer runners (shell scripts), so that the
// peer column's calling conventions, time offset and failures are checked without KISS-ICP or
// GenZ-ICP being built (../shared/peers builds the real ones).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace dammloam {
namespace {

using test::CommandResult;

const std::string kBench = std::string(DAMMLOAM_BIN_DIR) + "/dammloam-bench-odometry";

// Writes an executable /bin/sh script.
void WriteScript(const std::filesystem::path& file, const std::string& body) {
  std::filesystem::create_directories(file.parent_path());
  test::WriteText(file, "#!/bin/sh\n" + body);
  chmod(file.c_str(), 0755);
}

// A shared-peers runner (`RUNNER SEQ_DIR OUT.tum`) that reports, at each scan's start stamp, the
// true pose at the scan's END (the next scan's start), as KISS-ICP does, in 1.5 ms per scan:
// evaluated at stamp + one scan period its APE is zero.
const char* kEndOfScanRunner = R"(
awk '{ t[NR] = $1; p[NR] = $2 " " $3 " " $4 " " $5 " " $6 " " $7 " " $8 }
     END { for (i = 1; i < NR; ++i) print t[i], p[i + 1] }' "$1/gt.tum" > "$2"
n=$(wc -l < "$2")
awk '{ print "1.5" }' "$2" > "$ANCHOR_TIMES_OUT"
echo "[kiss] scans=$n per-scan time (ms): mean=1.500 median=1.500"
)";

class BenchPeerCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kBench)) GTEST_SKIP() << "dammloam-bench-odometry not built in " << DAMMLOAM_BIN_DIR;
  }
  // Five VLP-16 scans of a preset, one mode: the smallest run that evaluates a trajectory.
  CommandResult Bench(const std::string& peers) {
    return test::RunCommand(kBench + " --presets wheeled-zigzag --sensors vlp-16 --seeds 1 --scans 5 "
                            "--modes point_to_point --quiet " + peers + " 2>&1");
  }
  std::string Path(const std::string& name) const { return (tmp_ / name).string(); }

  test::TempDir tmp_;
};

TEST_F(BenchPeerCli, ASharedRunnerIsCalledByItsConventionAndEvaluatedAtTheScansEnd) {
  WriteScript(tmp_ / "good" / "kiss_run", kEndOfScanRunner);
  const CommandResult run = Bench("--peer kiss=" + Path("good/kiss_run"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("anchor runner, by its file name"), std::string::npos) << run.output;
  // The row names the offset; APE 0 at stamp + 0.1 s; the runner's own 1.5 ms.
  const auto row = run.output.find("kiss +0.100s");
  ASSERT_NE(row, std::string::npos) << run.output;
  EXPECT_EQ(run.output.substr(row + 22, 14), "  0.000  0.000") << run.output;
  EXPECT_NE(run.output.find("  1.5/1.5", row), std::string::npos) << run.output;
}

TEST_F(BenchPeerCli, TheOffsetCanBeSetAndZeroShowsTheEndOfScanLag) {
  WriteScript(tmp_ / "good" / "kiss_run", kEndOfScanRunner);
  const CommandResult run = Bench("--peer kiss=" + Path("good/kiss_run") + " --peer-offset kiss=0");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto row = run.output.find("kiss +0.000s");
  ASSERT_NE(row, std::string::npos) << run.output;
  EXPECT_NE(run.output.substr(row + 22, 14), "  0.000  0.000") << run.output;
}

TEST_F(BenchPeerCli, RunnersThatGiveNothingSayWhyAndFailTheRun) {
  WriteScript(tmp_ / "silent" / "kiss_run", "exit 0\n");
  // A shared runner called in the bench's own convention (`SEQ --out POSES ...`) takes POSES for
  // an unknown option and exits 2, as kiss_run does: that was the "no result" of issue 57.
  WriteScript(tmp_ / "usage" / "runner", "echo \"unknown option $3\" >&2\nexit 2\n");
  const CommandResult run =
      Bench("--peer silent=" + Path("silent/kiss_run") + " --peer usage=" + Path("usage/runner"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const auto silent = run.output.find("  silent +0.100s ");
  ASSERT_NE(silent, std::string::npos) << run.output;
  EXPECT_NE(run.output.find("no result: seed 1: no poses in", silent), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("(it printed nothing)", silent), std::string::npos) << run.output;
  const auto usage = run.output.find("  usage +0.000s ");
  ASSERT_NE(usage, std::string::npos) << run.output;
  EXPECT_NE(run.output.find("no result: seed 1: exit code 2 (it reads `RUNNER SEQ_DIR OUT.tum`", usage),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("--peer usage=anchor:" + Path("usage/runner"), usage), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("error: 2 peer run(s) gave no result"), std::string::npos) << run.output;
}

TEST_F(BenchPeerCli, AMissingRunnerStopsBeforeAnythingRuns) {
  const CommandResult run = Bench("--peer kiss=" + Path("none/kiss_run"));
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("error: --peer kiss: '" + Path("none/kiss_run") + "' is not an executable"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("build.sh"), std::string::npos) << run.output;
}

TEST_F(BenchPeerCli, AnOffsetForAnUnknownPeerIsRefused) {
  WriteScript(tmp_ / "good" / "kiss_run", kEndOfScanRunner);
  const CommandResult run = Bench("--peer kiss=" + Path("good/kiss_run") + " --peer-offset genz=0.05");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--peer-offset 'genz=0.05'"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace dammloam
