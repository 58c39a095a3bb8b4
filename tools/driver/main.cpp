// dammloam-driver: real Ouster / Velodyne packets (pcap replay or live UDP) -> PointCloud on
// DDS, a sequence directory (--to-sequence) and/or a raw range dump (--dump-range, Ouster).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <csignal>
#include <optional>

#include "drivers/ouster/metadata.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "tools/driver/dds_sink.hpp"
#include "tools/driver/driver_loop.hpp"
#include "tools/driver/sequence_sink.hpp"

namespace {

using namespace dammloam;

std::atomic<bool> g_stop{false};
extern "C" void OnSignal(int) { g_stop = true; }

struct CommonOptions {
  std::string pcap;
  int udp_port = -1;
  std::string bind = "0.0.0.0";
  std::string to_sequence;
  std::string write_meta;
  bool overwrite = false;
  std::optional<int> domain;
  std::string topic;
  std::string frame_id = "lidar";
  bool allow_default_network = false;
  double wait_for_subscriber = 0.0;
  double rate = -1.0;  // -1: recorded rate when publishing, as fast as possible otherwise
  std::size_t max_scans = 0;
  double idle_timeout = 0.0;
};

struct OusterOptions {
  std::string metadata;
  std::string dump_range;
  bool second_return = false;
  bool signal_intensity = false;
  int lidar_port = -1;
};

struct VelodyneOptions {
  std::string model;
  std::string calibration;
  double rpm = 600.0;
  double scan_phase = 0.0;
  double min_range = 0.3;
  double max_range = 200.0;
  bool single_return = false;
  int port = 2368;
};

void AddCommon(CLI::App* app, CommonOptions& o) {
  auto* pcap = app->add_option("--pcap", o.pcap, "replay this capture file")->check(CLI::ExistingFile);
  auto* udp = app->add_option("--udp-port", o.udp_port, "listen live on this UDP port")->check(CLI::Range(1, 65535));
  pcap->excludes(udp);
  app->add_option("--bind", o.bind, "live mode: local IPv4 address to bind");
  app->add_option("--to-sequence", o.to_sequence, "write the scans as a sequence directory");
  app->add_option("--write-meta", o.write_meta, "write the sensor description as meta.json (for dammloamd --sensor-meta)");
  app->add_flag("--overwrite", o.overwrite, "replace scans already in the --to-sequence directory");
  app->add_option("--domain", o.domain, "publish PointCloud on this DDS domain (default 0 when nothing else is asked)")
      ->check(CLI::Range(0, 232));
  app->add_option("--topic", o.topic, "DDS topic (default: the daemon's points topic)");
  app->add_option("--frame-id", o.frame_id, "frame_id of published clouds");
  app->add_flag("--allow-default-network", o.allow_default_network, "allow DDS without CYCLONEDDS_URI");
  app->add_option("--wait-for-subscriber", o.wait_for_subscriber,
                  "before publishing the first scan, wait up to this many seconds for a reader");
  app->add_option("--rate", o.rate, "pcap replay speed (1 = recorded rate, 0 = as fast as possible)")
      ->check(CLI::Range(0.0, 1000.0));
  app->add_option("--max-scans", o.max_scans, "stop after this many scans (0 = no limit)");
  app->add_option("--idle-timeout", o.idle_timeout, "live mode: stop after this many seconds without packets (0 = never)");
}

std::string SensorName(const std::string& prod_line) {
  // "OS-1-128" -> "os1-128", as in sequence.md's meta.json example.
  std::string s = prod_line.empty() ? "ouster" : prod_line;
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (s.rfind("os-", 0) == 0) s.erase(2, 1);
  return s;
}

int Run(CommonOptions& c, std::uint16_t sensor_port, const SensorModel& model, const std::string& sensor,
        driver::ScanDecoder& decoder, bool has_file_output) {
  if (c.pcap.empty() && c.udp_port < 0) {
    spdlog::error("give --pcap FILE or --udp-port PORT");
    return 1;
  }
  if (!c.write_meta.empty()) io::WriteMeta(c.write_meta, io::SequenceMeta{sensor, model});
  const bool publish = c.domain.has_value() || !has_file_output;
  std::vector<std::unique_ptr<driver::ScanSink>> sinks;
  if (!c.to_sequence.empty()) {
    sinks.push_back(std::make_unique<driver::SequenceSink>(c.to_sequence, io::SequenceMeta{sensor, model}, c.overwrite));
  }
  if (publish) {
    sinks.push_back(driver::MakeDdsSink(
        {c.domain.value_or(0), c.topic, c.frame_id, c.allow_default_network, c.wait_for_subscriber}));
  }

  driver::SourceOptions so;
  if (!c.pcap.empty()) so.pcap = c.pcap;
  if (c.udp_port > 0) so.udp_port = static_cast<std::uint16_t>(c.udp_port);
  so.sensor_port = sensor_port;
  so.bind_address = c.bind;
  so.rate = c.rate >= 0.0 ? c.rate : (publish ? 1.0 : 0.0);
  so.idle_timeout_s = c.idle_timeout;
  auto source = driver::MakeSource(so);

  spdlog::info("reading {} ({} rings x {} columns, {:.3f} s/scan)", source->Describe(), model.rings, model.columns,
               model.scan_period);
  for (const auto& s : sinks) spdlog::info("writing to {}", s->Describe());
  const driver::LoopResult r = driver::RunLoop(*source, decoder, sinks, c.max_scans, g_stop);

  spdlog::info("{} datagrams, {} scans", r.packets, r.scans);
  if (const auto* d = source->diagnostics(); d != nullptr) spdlog::info("input: {}", d->Summary());
  spdlog::info("decoder: {}", decoder.diagnostics().Summary());
  for (const auto& m : decoder.diagnostics().messages()) spdlog::warn("{}", m);
  if (r.scans == 0 && !g_stop) {
    spdlog::error("no complete scan was decoded (see the diagnostics above)");
    return 2;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dammloam-driver: Ouster/Velodyne packets to PointCloud (DDS), sequence directories, range dumps"};
  app.require_subcommand(1);
  CommonOptions common;
  OusterOptions os;
  VelodyneOptions vel;

  auto* ouster = app.add_subcommand("ouster", "Ouster OS0/OS1/OS2 (LEGACY and RNG19/RNG15/FUSA profiles)");
  ouster->add_option("--metadata", os.metadata, "sensor metadata JSON")->required()->check(CLI::ExistingFile);
  ouster->add_option("--dump-range", os.dump_range, "append each complete frame's staggered range image (uint32 LE mm)");
  ouster->add_flag("--second-return", os.second_return, "dual profiles: also publish second returns");
  ouster->add_flag("--signal-intensity", os.signal_intensity, "intensity = signal instead of reflectivity");
  ouster->add_option("--lidar-port", os.lidar_port, "pcap: lidar UDP port (default: from the metadata)");
  AddCommon(ouster, common);

  auto* velodyne = app.add_subcommand("velodyne", "Velodyne VLP-16, VLP-32C, HDL-32E, VLS-128");
  velodyne->add_option("--model", vel.model, "sensor model")->required()->check(CLI::IsMember({"vlp16", "vlp32c", "hdl32e", "vls128"}));
  velodyne->add_option("--calibration", vel.calibration, "calibration YAML (ROS velodyne / nebula layout)")
      ->required()->check(CLI::ExistingFile);
  velodyne->add_option("--rpm", vel.rpm, "nominal spin rate")->check(CLI::Range(60.0, 1500.0));
  velodyne->add_option("--scan-phase", vel.scan_phase, "azimuth (deg) where scans are cut")->check(CLI::Range(0.0, 360.0));
  velodyne->add_option("--min-range", vel.min_range, "metres");
  velodyne->add_option("--max-range", vel.max_range, "metres");
  velodyne->add_flag("--single-return", vel.single_return, "dual-return streams: keep only the first return");
  velodyne->add_option("--sensor-port", vel.port, "pcap: data UDP port")->check(CLI::Range(1, 65535));
  AddCommon(velodyne, common);

  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);

  try {
    if (ouster->parsed()) {
      const auto meta = drivers::ouster::LoadMetadata(os.metadata);
      std::optional<std::filesystem::path> dump;
      if (!os.dump_range.empty()) dump = os.dump_range;
      auto decoder = driver::MakeOusterDecoder(meta, {os.second_return, os.signal_intensity}, dump);
      const auto port = static_cast<std::uint16_t>(os.lidar_port > 0 ? os.lidar_port : meta.udp_port_lidar);
      return Run(common, port, drivers::ouster::ToSensorModel(meta), SensorName(meta.prod_line), *decoder,
                 !common.to_sequence.empty() || dump.has_value());
    }
    drivers::velodyne::DecoderConfig config;
    config.model = *drivers::velodyne::ParseModel(vel.model);
    config.rpm = vel.rpm;
    config.scan_phase_deg = vel.scan_phase;
    config.min_range = vel.min_range;
    config.max_range = vel.max_range;
    config.dual_both_returns = !vel.single_return;
    auto decoder = driver::MakeVelodyneDecoder(config, drivers::velodyne::LoadCalibration(vel.calibration));
    const SensorModel model = drivers::velodyne::Decoder(config, drivers::velodyne::LoadCalibration(vel.calibration)).sensor_model();
    return Run(common, static_cast<std::uint16_t>(vel.port), model, vel.model, *decoder, !common.to_sequence.empty());
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
