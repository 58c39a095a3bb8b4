// Failures caught inside dammloamd's stages are counted in Status and published as error events,
// not only logged (loopback DDS, own domain per test). Failures are injected through the
// daemon's test seam (FaultInjector): a back-end pass that throws turns DaemonStatus.loop_closure to
// "failed" and the state to DEGRADED while poses keep coming; a receive and a publish failure
// each cost one scan, are counted once, and tracking goes on.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>

#include "services/dammloamd/daemon.hpp"
#include "tests/system/daemon_test_config.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/system/sim_sequence.hpp"

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;
constexpr milliseconds kTimeout(60000);  // sanitizer builds are slow
constexpr milliseconds kStatusWait(10000);

// The pipeline set-up with the back-end on (its failures are what these tests inject).
daemon::DaemonConfig FailureTestConfig(std::uint32_t domain, const sim::Simulator& simulator) {
  daemon::DaemonConfig config = PipelineTestConfig(domain, simulator);
  config.loop_closure = true;
  config.labelled_cloud_every = 0;
  config.status_period = 0.1;
  return config;
}

// Throws in a chosen stage: `always` in the back-end, once per arming in the others.
struct Faults {
  std::atomic<bool> backend{false};
  std::atomic<int> receive{0}, publish{0};  // failures still to inject

  daemon::FaultInjector Injector() {
    return [this](daemon::Stage stage) {
      if (stage == daemon::Stage::kBackend && backend) {
        throw std::runtime_error("injected back-end failure");
      }
      if (stage == daemon::Stage::kReceive && receive.fetch_sub(1) > 0) {
        throw std::runtime_error("injected receive failure");
      }
      if (stage == daemon::Stage::kPublish && publish.fetch_sub(1) > 0) {
        throw std::runtime_error("injected publish failure");
      }
    };
  }
};

dds::CloudMessage Cloud(const sim::Simulator& simulator, int i) {
  return dds::ScanToCloud(simulator.SimulateScan(i), "lidar", static_cast<std::uint64_t>(i));
}

// Publishes scan i and waits for its pose.
void Track(DdsTestClient& client, const sim::Simulator& simulator, int i) {
  const dds::CloudMessage cloud = Cloud(simulator, i);
  client.Publish(cloud);
  EXPECT_TRUE(client.WaitForPose(cloud.stamp, kTimeout)) << "no pose for scan " << i;
}

// Waits for a periodic (not error-event) Status satisfying pred; returns the last Status seen.
template <typename Pred>
ReceivedStatus WaitForStatus(DdsTestClient& client, Pred&& pred) {
  const bool seen = client.WaitUntil([&] {
    return !client.statuses.empty() && !client.statuses.back().is_error_event &&
           pred(client.statuses.back());
  }, kStatusWait);
  EXPECT_TRUE(seen) << "no such Status";
  return client.statuses.empty() ? ReceivedStatus{} : client.statuses.back();
}

TEST(DaemonFailures, BackEndFailureIsCountedAndLoopClosureReportsFailed) {
  UseLoopbackDds();
  constexpr std::uint32_t kDomain = 186;
  const sim::Simulator simulator = SmallSimulator(8);
  Faults faults;
  daemon::Daemon daemon(FailureTestConfig(kDomain, simulator), OdometryConfig{},
                        faults.Injector());
  daemon.Start();
  DdsTestClient client(kDomain);
  ASSERT_TRUE(client.WaitForDaemon(milliseconds(10000)));

  for (int i = 0; i < 3; ++i) Track(client, simulator, i);
  ReceivedStatus status = WaitForStatus(client, [](const ReceivedStatus& s) {
    return s.processed == 3;
  });
  EXPECT_EQ(status.loop_closure, "ok");
  EXPECT_EQ(status.backend_errors, 0u);
  EXPECT_EQ(status.state, dammloam_msg_STATE_TRACKING);

  faults.backend = true;
  for (int i = 3; i < 8; ++i) Track(client, simulator, i);  // odometry is not held up
  const auto error = client.WaitForError("injected back-end failure", kStatusWait);
  ASSERT_TRUE(error);
  EXPECT_NE(error->find("loop closure back-end failed"), std::string::npos) << *error;
  status = WaitForStatus(client, [](const ReceivedStatus& s) {
    return s.processed == 8 && s.backend_errors > 0;
  });
  EXPECT_EQ(status.loop_closure, "failed");
  EXPECT_EQ(status.state, dammloam_msg_STATE_DEGRADED);
  EXPECT_EQ(status.receive_errors, 0u);
  EXPECT_EQ(status.publish_errors, 0u);

  // The back-end's state after a failed pass is unknown: "failed" does not wear off.
  faults.backend = false;
  std::this_thread::sleep_for(milliseconds(500));  // a few back-end passes (every 200 ms)
  status = WaitForStatus(client, [](const ReceivedStatus&) { return true; });
  EXPECT_EQ(status.loop_closure, "failed");
  daemon.Stop();
}

TEST(DaemonFailures, ReceiveAndPublishFailuresAreCountedAndTrackingGoesOn) {
  UseLoopbackDds();
  constexpr std::uint32_t kDomain = 187;
  const sim::Simulator simulator = SmallSimulator(6);
  Faults faults;
  daemon::DaemonConfig config = FailureTestConfig(kDomain, simulator);
  config.loop_closure = false;  // not needed here
  daemon::Daemon daemon(config, OdometryConfig{}, faults.Injector());
  daemon.Start();
  DdsTestClient client(kDomain);
  ASSERT_TRUE(client.WaitForDaemon(milliseconds(10000)));
  Track(client, simulator, 0);

  faults.receive = 1;
  client.Publish(Cloud(simulator, 1));  // lost in the receive stage
  EXPECT_TRUE(client.WaitForError("injected receive failure", kStatusWait));
  Track(client, simulator, 2);

  faults.publish = 1;
  client.Publish(Cloud(simulator, 3));  // registered, but its pose is never written
  EXPECT_TRUE(client.WaitForError("injected publish failure", kStatusWait));
  Track(client, simulator, 4);
  Track(client, simulator, 5);

  const ReceivedStatus status = WaitForStatus(client, [](const ReceivedStatus& s) {
    return s.processed == 4 && s.receive_errors == 1 && s.publish_errors == 1;
  });
  EXPECT_EQ(status.received, 6u);
  EXPECT_EQ(status.backend_errors, 0u);
  EXPECT_EQ(status.loop_closure, "off");
  EXPECT_EQ(client.CountPoses(Cloud(simulator, 1).stamp), 0u);
  EXPECT_EQ(client.CountPoses(Cloud(simulator, 3).stamp), 0u);
  daemon.Stop();
}

}  // namespace
}  // namespace dammloam::test
