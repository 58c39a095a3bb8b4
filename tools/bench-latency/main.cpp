// dammloam-bench-latency: end-to-end latency of dammloamd over DDS (publish of a scan -> receipt
// of its pose, median and p99) for simulated OS1-64 x 1024 scans at fixed rates, and the highest
// rate sustained without drops. Starts one fresh dammloamd per rate (or uses --external).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>

#include "tools/common/dds_tool_main.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "tools/common/sequence_meta.hpp"
#include "tools/simulate/simulator.hpp"

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;
using namespace dammloam;

struct Options {
  std::uint32_t domain = 90;
  int scans = 100;
  std::vector<double> rates = {10.0, 20.0};
  std::vector<double> sweep = {25.0, 30.0, 40.0};
  std::vector<double> fallback = {5.0, 2.0, 1.0};  // tried downwards when no rate held
  std::string sensor = "os1-64";
  std::string scene = "corridor";
  bool external = false;
  std::string daemon_args;
  bool allow_default_network = false;
};

struct RunResult {
  double rate = 0;
  std::size_t sent = 0, received = 0;
  double median_ms = 0, p99_ms = 0, max_ms = 0;
  double core_median_ms = 0;  // Odometry.processing_ms: features + registration + map
  bool sustained() const { return received == sent; }
};

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

// dammloamd next to this executable, as a child process; killed (SIGTERM) by the destructor.
class DaemonChild {
 public:
  DaemonChild(const Options& o, const std::filesystem::path& meta) {
    const std::string exe = (std::filesystem::read_symlink("/proc/self/exe").parent_path() /
                             "dammloamd").string();
    std::vector<std::string> args = {exe, "--domain", std::to_string(o.domain), "--sensor-meta",
                                     meta.string(), "--no-loop-closure", "--log-level", "warn"};
    std::istringstream extra(o.daemon_args);
    for (std::string a; extra >> a;) args.push_back(a);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // The daemon's log (drop warnings) goes to a file next to the temporary meta.json.
    const std::string log = meta.string() + ".dammloamd.log";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    const int rc = posix_spawn(&pid_, exe.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error("cannot start " + exe);
  }
  ~DaemonChild() {
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
  }

 private:
  pid_t pid_ = -1;
};

RunResult RunRate(const Options& o, const std::vector<dds::CloudMessage>& clouds, double rate,
                  double stamp_base) {
  dds::Participant participant(static_cast<dds_domainid_t>(o.domain));
  const dds::TopicNames names;
  dds::Topic points_topic(participant, dammloam_msg_PointCloud_desc, names.points, dds::PointsQos());
  dds::Writer<dammloam_msg_PointCloud> writer(participant, points_topic, dds::PointsQos());
  dds::Topic odom_topic(participant, dammloam_msg_Odometry_desc, names.odometry, dds::OdometryQos());
  dds::Reader<dammloam_msg_Odometry> reader(participant, odom_topic, {true, 1000, false});
  if (!writer.WaitForReaders(1, std::chrono::seconds(30))) {
    throw std::runtime_error("no dammloamd on domain " + std::to_string(o.domain));
  }
  while (reader.MatchedWriters() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // discovery settles

  std::map<std::pair<std::int32_t, std::uint32_t>, Clock::time_point> sent_at;
  std::vector<double> latencies_ms, processing_ms;
  const auto take = [&] {
    reader.TakeEach([&](const dammloam_msg_Odometry& m, const dds_sample_info_t&) {
      const auto it = sent_at.find({m.header.stamp.sec, m.header.stamp.nanosec});
      if (it == sent_at.end()) return;
      latencies_ms.push_back(
          std::chrono::duration<double, std::milli>(Clock::now() - it->second).count());
      processing_ms.push_back(m.processing_ms);
    }, 64);
  };
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate));
  const auto t0 = Clock::now();
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    dds::CloudMessage cloud = clouds[k];
    cloud.stamp = dds::ToMsgTime(stamp_base + static_cast<double>(k) / rate);
    const auto due = t0 + static_cast<long>(k) * period;
    while (Clock::now() < due) {
      take();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    sent_at[{cloud.stamp.sec, cloud.stamp.nanosec}] = Clock::now();
    writer.Write(dds::CloudView(cloud).get());
  }
  const auto deadline = Clock::now() + std::chrono::seconds(3);
  while (Clock::now() < deadline && latencies_ms.size() < clouds.size()) {
    take();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  RunResult r;
  r.rate = rate;
  r.sent = clouds.size();
  r.received = latencies_ms.size();
  r.median_ms = Percentile(latencies_ms, 0.5);
  r.p99_ms = Percentile(latencies_ms, 0.99);
  r.core_median_ms = Percentile(processing_ms, 0.5);
  r.max_ms = latencies_ms.empty() ? 0.0 : *std::max_element(latencies_ms.begin(), latencies_ms.end());
  return r;
}

int Run(const Options& o) {
  const auto sensor_spec = sim::MakeSensorSpec(o.sensor);
  const auto scene = sim::ParseSceneKind(o.scene);
  if (!sensor_spec || !scene) throw std::runtime_error("unknown --sensor or --scene");
  sim::SimOptions sim_options;
  sim_options.num_scans = o.scans;
  const sim::Simulator simulator(*scene, *sensor_spec, sim_options);
  spdlog::info("simulating {} {} scans in {}...", o.scans, o.sensor, o.scene);
  std::vector<dds::CloudMessage> clouds;
  for (int i = 0; i < o.scans; ++i) {
    clouds.push_back(dds::ScanToCloud(simulator.SimulateScan(i), "lidar", static_cast<std::uint64_t>(i)));
  }
  spdlog::info("{} points per scan, {:.1f} MiB per sample", clouds.front().width,
               static_cast<double>(clouds.front().data.size()) / (1 << 20));
  const auto meta_path = std::filesystem::temp_directory_path() /
                         ("dammloam-bench-latency-" + std::to_string(::getpid()) + ".json");
  io::WriteMeta(meta_path, {o.sensor, simulator.sensor_model(), io::PointLayout::kXYZITR});

  std::vector<RunResult> results;
  const auto run = [&](double rate) {
    std::optional<DaemonChild> daemon;
    if (!o.external) daemon.emplace(o, meta_path);
    const RunResult r = RunRate(o, clouds, rate, 1700000000.0 + 100000.0 * static_cast<double>(results.size()));
    std::printf("rate %5.1f Hz: %zu/%zu poses, latency median %.1f ms, p99 %.1f ms, max %.1f ms, "
                "core median %.1f ms/scan%s\n", r.rate, r.received, r.sent, r.median_ms, r.p99_ms,
                r.max_ms, r.core_median_ms, r.sustained() ? "" : "  (DROPS)");
    std::fflush(stdout);
    results.push_back(r);
    return r;
  };
  for (double rate : o.rates) run(rate);
  double best = 0.0;
  for (const auto& r : results) {
    if (r.sustained()) best = std::max(best, r.rate);
  }
  for (double rate : o.sweep) {
    if (rate <= best) continue;
    if (!run(rate).sustained()) break;
    best = rate;
  }
  if (best == 0.0) {
    for (double rate : o.fallback) {
      if (run(rate).sustained()) {
        best = rate;
        break;
      }
    }
  }
  std::filesystem::remove(meta_path);
  std::printf("highest rate sustained without drops: %.1f Hz (of those tried)\n", best);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"dammloam-bench-latency: dammloamd end-to-end latency over DDS"};
  app.add_option("--domain", o.domain, "DDS domain id");
  app.add_option("--scans", o.scans, "scans per rate")->check(CLI::PositiveNumber);
  app.add_option("--rates", o.rates, "rates to measure, Hz")->delimiter(',');
  app.add_option("--sweep", o.sweep, "higher rates tried until drops appear, Hz")->delimiter(',');
  app.add_option("--sensor", o.sensor, "simulated sensor (os1-64, vlp-16)");
  app.add_option("--scene", o.scene, "simulated scene");
  app.add_option("--fallback", o.fallback, "lower rates tried when none held, Hz")->delimiter(',');
  app.add_flag("--external", o.external, "use a running dammloamd instead of starting one");
  app.add_option("--daemon-args", o.daemon_args, "extra dammloamd arguments");
  app.add_flag("--allow-default-network", o.allow_default_network,
               "run without CYCLONEDDS_URI (uses the default network interface)");
  CLI11_PARSE(app, argc, argv);
  return tools::RunDdsTool(o.allow_default_network, [&] { return Run(o); });
}
