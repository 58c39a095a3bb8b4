// dammloam-bench-decode: packet decoding throughput per sensor on the shared real captures.
// Captures are read into memory first, so the numbers are decode (+ point cloud) cost only.
// Prints the median over --repeat runs of packets/s and scans/s.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "drivers/velodyne/decoder.hpp"

namespace {

using namespace dammloam::drivers;
namespace fs = std::filesystem;

std::vector<UdpDatagram> LoadDatagrams(const fs::path& pcap, std::uint16_t port) {
  PcapReader reader(pcap, PcapFilter{port});
  std::vector<UdpDatagram> out;
  for (UdpDatagram d; reader.Next(d);) out.push_back(d);
  return out;
}

// Runs `decode_all` (returns the scan count) `repeat` times and prints median rates.
void Report(const std::string& name, std::size_t packets, int repeat, const std::function<std::size_t()>& decode_all) {
  std::vector<double> seconds;
  std::size_t scans = 0;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    scans = decode_all();
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  std::printf("%-46s %6zu packets %3zu scans  median %8.2f ms  %10.0f packets/s  %8.1f scans/s\n", name.c_str(),
              packets, scans, median * 1e3, static_cast<double>(packets) / median, static_cast<double>(scans) / median);
}

void BenchOuster(const fs::path& dir, const std::string& pcap, const std::string& json, int repeat) {
  if (!fs::exists(dir / pcap)) return;
  const auto meta = ouster::LoadMetadata(dir / json);
  const auto packets = LoadDatagrams(dir / pcap, meta.udp_port_lidar);
  const ouster::CloudMaker cloud(meta);
  const std::string name = "ouster " + meta.prod_line + " " + std::string(ouster::Name(meta.profile));
  Report(name + " frames", packets.size(), repeat, [&] {
    ouster::PacketDecoder decoder(meta);
    std::size_t scans = 0;
    for (const auto& d : packets) scans += decoder.Push(d.payload).has_value();
    return scans;
  });
  Report(name + " +xyz", packets.size(), repeat, [&] {
    ouster::PacketDecoder decoder(meta);
    std::size_t scans = 0, points = 0;
    for (const auto& d : packets) {
      if (auto f = decoder.Push(d.payload)) {
        points += cloud.ToScan(*f).size();
        ++scans;
      }
    }
    return points > 0 ? scans : 0;
  });
}

void BenchVelodyne(const fs::path& pcap, velodyne::DecoderConfig config, const fs::path& calibration, int repeat) {
  if (!fs::exists(pcap) || !fs::exists(calibration)) return;
  const auto cal = velodyne::LoadCalibration(calibration);
  const auto packets = LoadDatagrams(pcap, 2368);
  Report("velodyne " + std::string(velodyne::Name(config.model)), packets.size(), repeat, [&] {
    velodyne::Decoder decoder(config, cal);
    std::size_t scans = 0;
    for (const auto& d : packets) scans += decoder.Push(d.payload, d.capture_time).has_value();
    return scans;
  });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dammloam-bench-decode: Ouster/Velodyne decode throughput on the shared real captures"};
  std::string data_dir = std::getenv("DAMMLOAM_DATA_DIR") != nullptr ? std::getenv("DAMMLOAM_DATA_DIR") : DAMMLOAM_BENCH_DATA_DIR;
  std::string calibration_dir = DAMMLOAM_BENCH_CALIBRATION_DIR;
  int repeat = 9;
  app.add_option("--data-dir", data_dir, "shared real-data folder");
  app.add_option("--calibration-dir", calibration_dir, "folder with HDL32E.yaml");
  app.add_option("--repeat", repeat, "runs per capture (the median is printed)")->check(CLI::Range(1, 1000));
  CLI11_PARSE(app, argc, argv);

  const fs::path data(data_dir);
  if (!fs::exists(data / "ouster_sdk_pcaps")) {
    std::fprintf(stderr, "no real captures under %s (use --data-dir)\n", data.c_str());
    return 1;
  }
  try {
    const fs::path os = data / "ouster_sdk_pcaps";
    BenchOuster(os, "OS-1-128_v2.3.0_1024x10_lb_n3.pcap", "OS-1-128_v2.3.0_1024x10.json", repeat);
    BenchOuster(os, "OS-0-32-U1_v2.2.0_1024x10.pcap", "OS-0-32-U1_v2.2.0_1024x10.json", repeat);
    BenchOuster(os, "OS-1-32-G_v2.1.1_1024x10.pcap", "OS-1-32-G_v2.1.1_1024x10.json", repeat);
    const fs::path neb = data / "velodyne_nebula_rosbag2";
    BenchVelodyne(neb / "vlp16/vlp16_packets_from_rosbag2.pcap", {.model = velodyne::Model::kVLP16},
                  neb / "calibration/VLP16.yaml", repeat);
    BenchVelodyne(neb / "vlp32/vlp32_packets_from_rosbag2.pcap",
                  {.model = velodyne::Model::kVLP32C, .min_range = 0.4, .max_range = 50.0, .scan_phase_deg = 180.0},
                  neb / "calibration/VLP32.yaml", repeat);
    BenchVelodyne(data / "velodyne_ouster_pcaps_rust_lidar_utils/hdl32e_example.pcap",
                  {.model = velodyne::Model::kHDL32E}, fs::path(calibration_dir) / "HDL32E.yaml", repeat);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
