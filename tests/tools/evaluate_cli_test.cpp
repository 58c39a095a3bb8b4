// Runs the built dammloam-evaluate binary on small files.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "io/tum.hpp"

namespace dammloam::eval {
namespace {

using test::CommandResult;

// Output is stdout only; a test that wants stderr too ends `arguments` with "2>&1".
CommandResult RunEvaluate(const std::string& arguments) {
  return test::RunCommand(std::string(DAMMLOAM_BIN_DIR) + "/dammloam-evaluate " + arguments);
}

class EvaluateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(std::string(DAMMLOAM_BIN_DIR) + "/dammloam-evaluate")) {
      GTEST_SKIP() << "dammloam-evaluate not built in " << DAMMLOAM_BIN_DIR;
    }
    std::vector<io::StampedPose> gt, est;
    for (int i = 0; i < 11; ++i) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(0.5 * i, 0.0, 0.0);
      gt.push_back({10.0 + 0.1 * i, T});
      T.translation().x() = 0.52 * i;  // 2 cm per frame too far
      est.push_back({10.0 + 0.1 * i + 0.001, T});
    }
    io::WriteTum(tmp_ / "gt.tum", gt);
    io::WriteTum(tmp_ / "est.tum", est);
  }
  std::string Path(const char* name) const { return (tmp_ / name).string(); }

  test::TempDir tmp_;
};

TEST_F(EvaluateCli, JsonOutput) {
  const CommandResult run = RunEvaluate(Path("gt.tum") + " " + Path("est.tum") + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto json = nlohmann::json::parse(run.output);
  EXPECT_EQ(json["pairs"], 11);
  EXPECT_NEAR(json["rpe"]["mean"].get<double>(), 0.02, 1e-9);
  EXPECT_NEAR(json["path_length_m"].get<double>(), 5.0, 1e-9);
  EXPECT_NEAR(json["drift_percent"].get<double>(), 4.0, 1e-6);
  EXPECT_GT(json["ape"]["max"].get<double>(), 0.0);
}

TEST_F(EvaluateCli, TableAndPlot) {
  const CommandResult run = RunEvaluate(Path("gt.tum") + " " + Path("est.tum") + " --plot " + Path("out.svg"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("APE"), std::string::npos) << run.output;
  EXPECT_EQ(test::ReadText(tmp_ / "out.svg").rfind("<svg", 0), 0u);
}

TEST_F(EvaluateCli, BadInputFailsNamingTheFile) {
  test::WriteText(tmp_ / "broken.tum", "0 1 2\n");
  const CommandResult run = RunEvaluate(Path("gt.tum") + " " + Path("broken.tum") + " --json 2>&1");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("broken.tum:1"), std::string::npos) << run.output;

  const CommandResult no_pairs = RunEvaluate(Path("gt.tum") + " " + Path("est.tum") + " --max-time-diff 0.0001 2>&1");
  EXPECT_EQ(no_pairs.exit_code, 1);
  EXPECT_NE(no_pairs.output.find("need at least 2"), std::string::npos) << no_pairs.output;
}

}  // namespace
}  // namespace dammloam::eval
