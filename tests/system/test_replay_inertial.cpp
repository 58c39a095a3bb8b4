// dammloam-replay publishes a sequence's imu.csv and wheel.csv (issue 55): every IMU sample up
// to the end of the last scan arrives, in order, with its values; --no-imu leaves them out.
#include <gtest/gtest.h>

#include <thread>

#include "io/sequence_io.hpp"
#include "services/dds/inertial_messages.hpp"
#include "services/dds/topics.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/system/child_process.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/system/sim_sequence.hpp"
#include "tools/simulate/inertial_streams.hpp"

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;

constexpr std::uint32_t kDomain = 147;
constexpr int kScans = 3;

struct Received {
  std::vector<ImuSample> imu;
  std::vector<WheelSample> wheel;
  int clouds = 0;
  std::string log;
};

// Runs dammloam-replay on `seq` with extra `args` while a subscriber collects what it sends.
Received Replay(const std::filesystem::path& seq, const std::vector<std::string>& args,
                const std::filesystem::path& log, int* exit_code) {
  dds::Participant participant(kDomain);
  const dds::TopicNames names;
  dds::Topic points(participant, dammloam_msg_PointCloud_desc, names.points, dds::PointsQos());
  dds::Reader<dammloam_msg_PointCloud> cloud_reader(participant, points, dds::PointsQos(16));
  dds::Topic imu(participant, dammloam_msg_Imu_desc, names.imu, dds::ImuQos());
  dds::Reader<dammloam_msg_Imu> imu_reader(participant, imu, dds::ImuQos());
  dds::Topic wheel(participant, dammloam_msg_WheelOdometry_desc, names.wheel_odometry, dds::WheelOdometryQos());
  dds::Reader<dammloam_msg_WheelOdometry> wheel_reader(participant, wheel, dds::WheelOdometryQos());
  std::vector<std::string> all = {seq.string(), "--domain", std::to_string(kDomain), "--rate", "5"};
  all.insert(all.end(), args.begin(), args.end());
  ChildProcess replay("dammloam-replay", all, log);
  Received got;
  const auto take = [&] {
    imu_reader.TakeEach(
        [&](const dammloam_msg_Imu& m, const dds_sample_info_t&) { got.imu.push_back(dds::FromImuMessage(m)); },
        256);
    wheel_reader.TakeEach(
        [&](const dammloam_msg_WheelOdometry& m, const dds_sample_info_t&) {
          got.wheel.push_back(dds::FromWheelMessage(m));
        },
        256);
    got.clouds += cloud_reader.TakeEach([](const dammloam_msg_PointCloud&, const dds_sample_info_t&) {});
  };
  std::optional<int> code;
  while (!(code = replay.Wait(milliseconds(20)))) take();
  std::this_thread::sleep_for(milliseconds(100));
  take();
  *exit_code = code.value_or(-1);
  got.log = replay.Log();
  return got;
}

TEST(ReplayInertial, PublishesTheSamplesBeforeTheScansTheyCover) {
  UseLoopbackDds();
  if (!ToolExists("dammloam-replay")) GTEST_SKIP() << "dammloam-replay not built";
  const TempDir dir("replay-inertial");
  const sim::Simulator simulator = SmallSimulator(kScans);
  WriteSequence(simulator, kScans, dir / "seq");
  sim::InertialStreamOptions options;
  options.imu.description.time_offset = 0.0;
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, options);
  io::WriteImuCsv(dir / "seq" / "imu.csv", *streams.imu);
  const double t0 = simulator.ScanStartTime(0);
  io::WriteWheelCsv(dir / "seq" / "wheel.csv", {{t0, {0.5, 0, 0}, Eigen::Vector3d::Zero()},
                                                {t0 + 0.1, {0.6, 0, 0}, Eigen::Vector3d(0, 0, 0.1)}});

  int code = -1;
  const Received got = Replay(dir / "seq", {}, dir / "replay.log", &code);
  ASSERT_EQ(code, 0) << got.log;
  EXPECT_EQ(got.clouds, kScans);
  // 31 samples over 0.3 s; the last lies on the last scan's end and may go either way.
  ASSERT_GE(got.imu.size(), 30u) << got.log;
  ASSERT_LE(got.imu.size(), streams.imu->size());
  for (std::size_t k = 0; k < got.imu.size(); ++k) {
    EXPECT_NEAR(got.imu[k].t, (*streams.imu)[k].t, 1e-6) << k;
    EXPECT_EQ(got.imu[k].angular_velocity, (*streams.imu)[k].angular_velocity) << k;
    EXPECT_EQ(got.imu[k].linear_acceleration, (*streams.imu)[k].linear_acceleration) << k;
  }
  ASSERT_EQ(got.wheel.size(), 2u);
  EXPECT_EQ(got.wheel[1].linear_velocity.x(), 0.6);

  const Received without = Replay(dir / "seq", {"--no-imu", "--no-wheel"}, dir / "replay2.log", &code);
  ASSERT_EQ(code, 0) << without.log;
  EXPECT_EQ(without.clouds, kScans);
  EXPECT_TRUE(without.imu.empty());
  EXPECT_TRUE(without.wheel.empty());
}

}  // namespace
}  // namespace dammloam::test
