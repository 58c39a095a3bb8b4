// dammloam-replay on recordings other than sequence directories (issue 54): the scans of a real
// Ouster capture arrive over DDS as the offline reader gives them, at the capture's own stamps,
// and --write-sensor-meta hands dammloamd the model they were read with; the latency benchmark
// replays the same capture into a dammloamd of its own.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "io/sequence_meta.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/system/child_process.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tools/inputs/scan_input.hpp"

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;

constexpr std::uint32_t kDomain = 148;

struct ReceivedCloud {
  double stamp = 0.0;
  std::size_t points = 0;
};

// Runs dammloam-replay with `args` while a subscriber collects the clouds it sends.
std::vector<ReceivedCloud> Replay(const std::vector<std::string>& args, const std::filesystem::path& log,
                                  int* exit_code, std::string* replay_log) {
  dds::Participant participant(kDomain);
  dds::Topic points(participant, dammloam_msg_PointCloud_desc, dds::TopicNames{}.points, dds::PointsQos());
  dds::Reader<dammloam_msg_PointCloud> reader(participant, points, dds::PointsQos(16));
  std::vector<std::string> all = args;
  all.insert(all.end(), {"--domain", std::to_string(kDomain), "--rate", "2"});
  ChildProcess replay("dammloam-replay", all, log);
  std::vector<ReceivedCloud> got;
  const auto take = [&] {
    reader.TakeEach([&](const dammloam_msg_PointCloud& m, const dds_sample_info_t&) {
      got.push_back({m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec,
                     static_cast<std::size_t>(m.width) * m.height});
    });
  };
  std::optional<int> code;
  while (!(code = replay.Wait(milliseconds(20)))) take();
  std::this_thread::sleep_for(milliseconds(100));
  take();
  *exit_code = code.value_or(-1);
  *replay_log = replay.Log();
  return got;
}

TEST(ReplayRecordings, OusterCaptureArrivesAsTheOfflineReaderGivesIt) {
  UseLoopbackDds();
  if (!ToolExists("dammloam-replay")) GTEST_SKIP() << "dammloam-replay not built";
  const std::filesystem::path pcap = DataDir() / "ouster_sdk_pcaps" / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  // What dammloam-odometry would read: three complete frames of an OS1-128 at 10 Hz.
  tools::ScanInputOptions input;
  input.path = pcap;
  input.quiet = true;
  const std::unique_ptr<io::ScanSource> source = tools::OpenScanInput(input);
  std::vector<ReceivedCloud> offline;
  while (std::optional<Scan> scan = source->Next()) offline.push_back({scan->t_start, scan->size()});
  ASSERT_EQ(offline.size(), 3u);

  const TempDir dir("replay-recordings");
  int code = -1;
  std::string log;
  const std::vector<ReceivedCloud> got =
      Replay({pcap.string(), "--write-sensor-meta", (dir / "meta.json").string()}, dir / "replay.log",
             &code, &log);
  ASSERT_EQ(code, 0) << log;
  ASSERT_EQ(got.size(), offline.size()) << log;
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_NEAR(got[k].stamp, offline[k].stamp, 1e-6) << k;  // the capture's stamps, not replay time
    EXPECT_EQ(got[k].points, offline[k].points) << k;
  }
  EXPECT_NEAR(got[2].stamp - got[0].stamp, 0.2, 0.005);
  const io::SequenceMeta meta = io::ReadMeta(dir / "meta.json");
  EXPECT_EQ(meta.model.rings, 128);
  EXPECT_EQ(meta.model.columns, 1024);
  EXPECT_NEAR(meta.model.scan_period, 0.1, 1e-6);

  // A later start and a count pick scans out of the capture; beyond its end is an error.
  const std::vector<ReceivedCloud> one =
      Replay({pcap.string(), "--start-index", "1", "--count", "1"}, dir / "replay2.log", &code, &log);
  ASSERT_EQ(code, 0) << log;
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one[0].stamp, offline[1].stamp, 1e-6);
  Replay({pcap.string(), "--start-index", "5"}, dir / "replay3.log", &code, &log);
  EXPECT_EQ(code, 2) << log;
  EXPECT_NE(log.find("beyond the recording's 3 scans"), std::string::npos) << log;
}

TEST(ReplayRecordings, LatencyBenchmarkReplaysACaptureIntoTheDaemon) {
  UseLoopbackDds();
  if (!ToolExists("dammloam-bench-latency") || !ToolExists("dammloamd")) {
    GTEST_SKIP() << "dammloam-bench-latency or dammloamd not built";
  }
  const std::filesystem::path pcap = DataDir() / "ouster_sdk_pcaps" / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const TempDir dir("bench-recording");
  ChildProcess bench("dammloam-bench-latency",
                     {"--domain", std::to_string(kDomain + 1), "--sequence", pcap.string(), "--json",
                      (dir / "latency.json").string()},
                     dir / "bench.log");
  const std::optional<int> code = bench.Wait(milliseconds(120000));
  ASSERT_TRUE(code.has_value()) << bench.Log();
  ASSERT_EQ(*code, 0) << bench.Log();
  std::ifstream in(dir / "latency.json");
  const auto report = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << bench.Log();
  const auto& run = report["runs"][0];
  EXPECT_EQ(run["sent"], 3);
  EXPECT_EQ(run["received"], 3) << bench.Log();
  EXPECT_EQ(run["drops"], 0);
  EXPECT_NEAR(run["rate_hz"].get<double>(), 10.0, 0.2);  // the capture's own 10 Hz
}

}  // namespace
}  // namespace dammloam::test
