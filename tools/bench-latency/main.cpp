// dammloam-bench-latency: end-to-end latency of dammloamd over DDS (publish of a scan -> receipt
// of its pose, median and p99). Two modes:
//  - simulated (default): OS1-64 x 1024 (or --sensor) scans at fixed rates, and the highest rate
//    sustained without drops; one fresh dammloamd per rate (or --external);
//  - --sequence DIR: a recorded sequence directory replayed at its recorded instants (times.txt,
//    --speed), with drops counted by us and by the daemon's Status; dammloamd gets the sequence's
//    meta.json.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "tools/bench-latency/daemon_child.hpp"
#include "tools/bench-latency/latency_run.hpp"
#include "tools/bench-latency/report.hpp"
#include "tools/bench-latency/sequence_source.hpp"
#include "tools/common/dds_tool_main.hpp"
#include "io/sequence_io.hpp"
#include "io/sequence_meta.hpp"
#include "tools/inputs/scan_input.hpp"
#include "tools/simulate/simulator.hpp"

namespace {

namespace fs = std::filesystem;
using namespace dammloam;
using bench::RunResult;

struct Options {
  std::uint32_t domain = 90;
  int scans = 100;
  bool scans_given = false;  // a sequence runs whole unless --scans is given
  std::vector<double> rates = {10.0, 20.0};
  std::vector<double> sweep = {25.0, 30.0, 40.0};
  std::vector<double> fallback = {5.0, 2.0, 1.0};  // tried downwards when no rate held
  std::string sensor = "os1-64";
  std::string scene = "corridor";
  std::string sequence;           // empty: simulated mode; else any recording tools/inputs reads
  tools::ScanInputOptions input;  // bags, captures, cloud folders: how to read them
  double speed = 1.0;             // over the recorded rate
  std::size_t read_ahead = 32;    // scans (an OS1-64 sample is ~1.5 MiB)
  std::string json_path;
  bool external = false;
  std::string daemon_args;
  bool allow_default_network = false;
};

// A file of this process in the temporary directory (meta.json, the daemon's log).
fs::path TempPath(const std::string& suffix) {
  return fs::temp_directory_path() /
         ("dammloam-bench-latency-" + std::to_string(::getpid()) + suffix);
}

// Simulated clouds held in memory, restamped per run so that the stamps keep increasing.
class SimulatedSource : public bench::ScanSource {
 public:
  SimulatedSource(const std::vector<dds::CloudMessage>& clouds, double rate, double stamp_base)
      : clouds_(clouds), rate_(rate), stamp_base_(stamp_base) {}
  std::size_t size() const override { return clouds_.size(); }
  bench::Clock::duration DueAfterStart(std::size_t index) const override {
    return std::chrono::duration_cast<bench::Clock::duration>(
        std::chrono::duration<double>(static_cast<double>(index) / rate_));
  }
  std::optional<dds::CloudMessage> TryTake(std::size_t index) override {
    dds::CloudMessage cloud = clouds_[index];
    cloud.stamp = dds::ToMsgTime(stamp_base_ + static_cast<double>(index) / rate_);
    return cloud;
  }

 private:
  const std::vector<dds::CloudMessage>& clouds_;
  double rate_, stamp_base_;
};

std::vector<dds::CloudMessage> SimulateClouds(const sim::Simulator& simulator, const Options& o) {
  spdlog::info("simulating {} {} scans in {}...", o.scans, o.sensor, o.scene);
  std::vector<dds::CloudMessage> clouds;
  for (int i = 0; i < o.scans; ++i) {
    clouds.push_back(
        dds::ScanToCloud(simulator.SimulateScan(i), "lidar", static_cast<std::uint64_t>(i)));
  }
  spdlog::info("{} points per scan, {:.1f} MiB per sample", clouds.front().width,
               static_cast<double>(clouds.front().data.size()) / (1 << 20));
  return clouds;
}

int RunSimulated(const Options& o) {
  const auto sensor_spec = sim::MakeSensorSpec(o.sensor);
  const auto scene = sim::ParseSceneKind(o.scene);
  if (!sensor_spec || !scene) throw std::runtime_error("unknown --sensor or --scene");
  sim::SimOptions sim_options;
  sim_options.num_scans = o.scans;
  const sim::Simulator simulator(*scene, *sensor_spec, sim_options);
  const std::vector<dds::CloudMessage> clouds = SimulateClouds(simulator, o);
  const fs::path meta_path = TempPath(".json");
  io::WriteMeta(meta_path, {o.sensor, simulator.sensor_model(), io::PointLayout::kXYZITR});

  std::vector<RunResult> results;
  const auto run = [&](double rate) {
    std::optional<bench::DaemonChild> daemon;
    if (!o.external) daemon.emplace(o.domain, meta_path, o.daemon_args, TempPath(".dammloamd.log"));
    SimulatedSource source(clouds, rate,
                           1700000000.0 + 100000.0 * static_cast<double>(results.size()));
    RunResult r = bench::RunScans({o.domain, false, ""}, source);
    r.rate = rate;
    bench::PrintRateRow(r);
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
  fs::remove(meta_path);
  std::printf("highest rate sustained without drops: %.1f Hz (of those tried)\n", best);
  if (!o.json_path.empty()) {
    nlohmann::json report{{"mode", "simulated"}, {"sensor", o.sensor}, {"scene", o.scene},
                          {"scans", o.scans}, {"highest_sustained_hz", best},
                          {"runs", nlohmann::json::array()}};
    for (const auto& r : results) report["runs"].push_back(bench::ToJson(r));
    bench::WriteJson(o.json_path, report);
  }
  return 0;
}

// dammloamd reads its sensor from a meta.json: the sequence's own, or for a KITTI folder (which
// has none) the reader's assumed sensor written to a temporary file.
fs::path SensorMetaFor(const io::SequenceReader& sequence) {
  const fs::path own = sequence.dir() / "meta.json";
  if (fs::exists(own)) return own;
  const fs::path written = TempPath(".json");
  io::WriteMeta(written, sequence.meta());
  return written;
}

std::size_t SequenceScanCount(const Options& o, const io::SequenceReader& sequence) {
  const std::size_t whole = sequence.size();
  if (!o.scans_given) return whole;
  const auto asked = static_cast<std::size_t>(o.scans);
  if (asked > whole) {
    spdlog::warn("--scans {}: {} has only {} scans; replaying all of them", asked,
                 sequence.dir().string(), whole);
  }
  return std::min(asked, whole);
}

// What the replay itself cost: how the read-ahead kept up and the benchmark's memory.
struct ReplayCost {
  std::size_t lowest_fill = 0;
  double read_ms = 0.0, peak_rss_mib = 0.0;
};

void PrintReplayCost(const Options& o, const ReplayCost& c, const fs::path& log) {
  std::printf("  read-ahead %zu scans: lowest fill %zu, read+convert mean %.1f ms/scan; bench "
              "peak RSS %.0f MiB\n", o.read_ahead, c.lowest_fill, c.read_ms, c.peak_rss_mib);
  if (!o.external) std::printf("  dammloamd log: %s\n", log.c_str());
  std::fflush(stdout);
}

void WriteSequenceJson(const Options& o, const RunResult& r, const ReplayCost& c) {
  nlohmann::json report{{"mode", "sequence"},
                        {"sequence", o.sequence},
                        {"speed", o.speed},
                        {"read_ahead", o.read_ahead},
                        {"read_ahead_lowest_fill", c.lowest_fill},
                        {"read_ms_mean", c.read_ms},
                        {"peak_rss_mib", c.peak_rss_mib},
                        {"runs", nlohmann::json::array({bench::ToJson(r)})}};
  bench::WriteJson(o.json_path, report);
}

// A recording other than a sequence directory: one pass for the stamps (a bag streams, so the
// publisher's schedule is known only by reading it), then a second source read as it is
// published. dammloamd gets the model the scans were read with as a meta.json.
struct Recording {
  std::unique_ptr<io::ScanSource> stamps_pass, source;
  bench::RecordedScans scans;
  io::SequenceMeta meta;
};

Recording OpenRecording(const Options& o) {
  Recording r;
  tools::ScanInputOptions input = o.input;
  input.path = o.sequence;
  r.stamps_pass = tools::OpenScanInput(input);
  input.quiet = true;
  r.source = tools::OpenScanInput(input);
  const std::size_t limit = o.scans_given ? static_cast<std::size_t>(o.scans) : 0;
  r.scans.name = o.sequence;
  while (limit == 0 || r.scans.times.size() < limit) {
    std::optional<Scan> scan = r.stamps_pass->Next();
    if (!scan) break;
    r.scans.times.push_back(scan->t_start);
  }
  if (r.scans.times.empty()) throw io::IoError(o.sequence + ": no scans");
  io::ScanSource* source = r.source.get();
  const std::string name = o.sequence;
  r.scans.read = [source, name](std::size_t) {
    std::optional<Scan> scan = source->Next();
    if (!scan) throw io::IoError(name + ": ended before its stamps pass did");
    return std::move(*scan);
  };
  r.meta.sensor = r.source->kind();
  r.meta.model = r.source->model();
  return r;
}

int RunSequence(const Options& o) {
  std::optional<io::SequenceReader> sequence;
  std::optional<Recording> recording;
  bench::RecordedScans scans;
  std::size_t count = 0;
  fs::path meta;
  std::string sensor;
  if (fs::is_directory(o.sequence) && fs::exists(fs::path(o.sequence) / "meta.json")) {
    sequence.emplace(io::SequenceReader::Open(o.sequence));
    count = SequenceScanCount(o, *sequence);
    bench::CheckScanFileSizes(*sequence, count);
    meta = SensorMetaFor(*sequence);
    scans = bench::SequenceScans(*sequence);
    sensor = sequence->meta().sensor;
  } else {
    recording.emplace(OpenRecording(o));
    scans = std::move(recording->scans);
    count = scans.times.size();
    meta = TempPath(".json");
    io::WriteMeta(meta, recording->meta);
    sensor = recording->meta.sensor;
  }
  const std::size_t whole = scans.times.size();
  const fs::path log = TempPath(".dammloamd.log");
  bench::SequenceSource source(std::move(scans), count, o.speed, o.read_ahead);
  spdlog::info("sequence {}: {} of {} {} scans at {:.2f} Hz ({}x the recorded rate), read-ahead {}",
               o.sequence, count, whole, sensor, source.Rate(), o.speed, o.read_ahead);
  std::optional<bench::DaemonChild> daemon;
  if (!o.external) daemon.emplace(o.domain, meta, o.daemon_args, log);
  source.WaitUntilFilled();
  RunResult r = bench::RunScans(
      {o.domain, true, o.external ? "" : "it was started with its log in " + log.string()},
      source);
  r.rate = source.Rate();
  daemon.reset();
  if (meta != fs::path(o.sequence) / "meta.json") fs::remove(meta);
  const ReplayCost cost{source.LowestFill(), source.MeanReadMs(), bench::PeakResidentMiB()};
  bench::PrintRateRow(r);
  bench::PrintDrops(r);
  PrintReplayCost(o, cost, log);
  if (!o.json_path.empty()) WriteSequenceJson(o, r, cost);
  return 0;
}

int Run(const Options& o) { return o.sequence.empty() ? RunSimulated(o) : RunSequence(o); }

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "dammloam-bench-latency: dammloamd end-to-end latency over DDS (publish of a scan -> its "
      "pose), on simulated scans at fixed rates or on a recorded sequence at its recorded rate"};
  app.footer(
      "Examples (CYCLONEDDS_URI=file://$PWD/deploy/cyclonedds-loopback.xml):\n"
      "  dammloam-bench-latency --rates 10,20            simulated OS1-64 scans, then a sweep\n"
      "  dammloam-bench-latency --sequence SEQ_DIR --scans 300 [--speed 2] [--json out.json]");
  app.add_option("--domain", o.domain, "DDS domain id");
  auto* scans = app.add_option("--scans", o.scans,
                               "scans per rate (simulated, default 100); with --sequence: the "
                               "first N scans (default: all)")
                    ->check(CLI::PositiveNumber);
  auto* sequence = app.add_option(
      "--sequence", o.sequence,
      "replay this recording at its recorded instants and report drops (ours and dammloamd's "
      "Status) and latency: a sequence directory (dammloamd gets its meta.json as --sensor-meta) or "
      "any input dammloam-odometry reads (rosbag2, .mcap, ROS 1 .bag, .pcap, cloud folder; "
      "dammloamd gets the model the scans were read with)");
  app.add_option("--topic", o.input.topic, "with --sequence, bags: the PointCloud2 (or packet) topic")
      ->needs(sequence);
  app.add_option("--sensor-meta", o.input.sensor_meta,
                 "with --sequence, bags and cloud folders: meta.json with the sensor model")->needs(sequence);
  app.add_option("--ouster-metadata", o.input.ouster_metadata,
                 "with --sequence, Ouster captures and packet bags: the metadata JSON")->needs(sequence);
  app.add_option("--velodyne-model", o.input.velodyne_model, "with --sequence, raw Velodyne packets")
      ->needs(sequence);
  app.add_option("--velodyne-calibration", o.input.velodyne_calibration,
                 "with --sequence, raw Velodyne packets: calibration YAML")->needs(sequence);
  app.add_option("--speed", o.speed, "with --sequence: speed factor over the recorded rate")
      ->check(CLI::PositiveNumber)->needs(sequence);
  app.add_option("--read-ahead", o.read_ahead,
                 "with --sequence: scans read ahead of the publisher on another thread "
                 "(memory: about N x 1.5 MiB for OS1-64)")
      ->check(CLI::PositiveNumber)->needs(sequence);
  app.add_option("--rates", o.rates, "rates to measure, Hz (simulated)")->delimiter(',')
      ->excludes(sequence);
  app.add_option("--sweep", o.sweep, "higher rates tried until drops appear, Hz (simulated)")
      ->delimiter(',')->excludes(sequence);
  app.add_option("--sensor", o.sensor, "simulated sensor (os1-64, vlp-16, os1-128, os1-128x2048, vls-128)")->excludes(sequence);
  app.add_option("--scene", o.scene, "simulated scene")->excludes(sequence);
  app.add_option("--fallback", o.fallback, "lower rates tried when none held, Hz (simulated)")
      ->delimiter(',')->excludes(sequence);
  app.add_option("--json", o.json_path, "also write the numbers to this JSON file");
  app.add_flag("--external", o.external, "use a running dammloamd instead of starting one");
  app.add_option("--daemon-args", o.daemon_args, "extra dammloamd arguments");
  app.add_flag("--allow-default-network", o.allow_default_network,
               "run without CYCLONEDDS_URI (uses the default network interface)");
  CLI11_PARSE(app, argc, argv);
  o.scans_given = scans->count() > 0;
  return tools::RunDdsTool(o.allow_default_network, [&] { return Run(o); });
}
