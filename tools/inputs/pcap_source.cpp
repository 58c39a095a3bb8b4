#include "tools/inputs/pcap_source.hpp"

#include <algorithm>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "io/io_error.hpp"
#include "tools/inputs/packet_scans.hpp"

namespace dammloam::tools {
namespace {

namespace fs = std::filesystem;
namespace ouster = drivers::ouster;
namespace velodyne = drivers::velodyne;

// What the capture held, for "no scan" errors: "120 records, 100 datagrams, other_ports=20".
std::string Held(const drivers::Diagnostics& pcap, const drivers::Diagnostics& decoder) {
  std::string s = "capture: " + (pcap.counters().empty() ? std::string("no records") : pcap.Summary());
  if (!decoder.counters().empty()) s += "; decoder: " + decoder.Summary();
  return s;
}

// Throws when libpcap stopped before the end of the file (a record cut short).
void CheckReadErrors(const fs::path& file, const drivers::Diagnostics& pcap) {
  if (pcap.Get("read_errors") == 0) return;
  for (const std::string& m : pcap.messages()) {
    if (m.rfind("read_errors: ", 0) == 0) throw io::IoError(file.string() + ": " + m.substr(13));
  }
  throw io::IoError(file.string() + ": pcap read error");
}

class OusterPcapSource : public io::ScanSource {
 public:
  OusterPcapSource(const fs::path& file, const fs::path& metadata, std::string metadata_origin)
      : file_(file),
        meta_(ouster::LoadMetadata(metadata)),
        reader_(file, drivers::PcapFilter{meta_.udp_port_lidar}),
        scans_(meta_),
        model_(ouster::ToSensorModel(meta_)),
        describe_("Ouster " + (meta_.prod_line.empty() ? std::string("sensor") : meta_.prod_line) + " " +
                  meta_.lidar_mode + ", profile " + std::string(ouster::Name(meta_.profile)) +
                  ", metadata " + metadata.string() + " (" + metadata_origin + "), lidar packets to UDP port " +
                  std::to_string(meta_.udp_port_lidar) + "; stamps from the column timestamps") {}

  std::string kind() const override { return "ouster pcap"; }
  std::string Describe() const override { return describe_; }
  const SensorModel& model() const override { return model_; }
  std::optional<std::size_t> size() const override { return std::nullopt; }
  std::optional<std::vector<io::StampedPose>> ReadGroundTruth() const override { return std::nullopt; }

  std::optional<Scan> Next() override {
    while (reader_.Next(datagram_)) {
      if (auto scan = scans_.Push(datagram_.payload)) return scan;
    }
    scans_.Flush();
    CheckReadErrors(file_, reader_.diagnostics());
    if (scans_.scans() == 0) {
      throw io::IoError(file_.string() + ": no complete Ouster frame with a return (lidar packets of " +
                        std::to_string(ouster::LayoutFor(meta_).packet) + " bytes to UDP port " +
                        std::to_string(meta_.udp_port_lidar) + "; " +
                        Held(reader_.diagnostics(), scans_.diagnostics()) + ")");
    }
    return std::nullopt;
  }

 private:
  fs::path file_;
  ouster::Metadata meta_;
  drivers::PcapReader reader_;
  OusterScans scans_;
  SensorModel model_;
  std::string describe_;
  drivers::UdpDatagram datagram_;
};

class VelodynePcapSource : public io::ScanSource {
 public:
  VelodynePcapSource(const fs::path& file, const std::string& model, const fs::path& calibration)
      : file_(file),
        reader_(file),
        decoder_(VelodyneDecoderConfig(model), velodyne::LoadCalibration(calibration)),
        model_(decoder_.sensor_model()),
        describe_("Velodyne " + model + " data packets (1206 bytes, any port), calibration " +
                  calibration.string() + "; scans cut at azimuth 0, stamps from the packets") {}

  std::string kind() const override { return "velodyne pcap"; }
  std::string Describe() const override { return describe_; }
  const SensorModel& model() const override { return model_; }
  std::optional<std::size_t> size() const override { return std::nullopt; }
  std::optional<std::vector<io::StampedPose>> ReadGroundTruth() const override { return std::nullopt; }

  std::optional<Scan> Next() override {
    while (reader_.Next(datagram_)) {
      if (datagram_.payload.size() != velodyne::kPacketSize) {
        ++other_datagrams_;  // position (GPS) packets, other traffic
        continue;
      }
      ++packets_;
      if (auto scan = decoder_.Push(datagram_.payload, datagram_.capture_time)) {
        ++scans_;
        return scan;
      }
    }
    decoder_.Flush();
    CheckReadErrors(file_, reader_.diagnostics());
    if (scans_ == 0) {
      throw io::IoError(file_.string() + ": no complete Velodyne scan (" + std::to_string(packets_) +
                        " data packets of 1206 bytes, " + std::to_string(other_datagrams_) +
                        " other UDP datagrams; " + Held(reader_.diagnostics(), decoder_.diagnostics()) + ")");
    }
    return std::nullopt;
  }

 private:
  fs::path file_;
  drivers::PcapReader reader_;
  velodyne::Decoder decoder_;
  SensorModel model_;
  std::string describe_;
  drivers::UdpDatagram datagram_;
  std::size_t packets_ = 0, other_datagrams_ = 0, scans_ = 0;
};

}  // namespace

bool IsPcapPath(const fs::path& path) {
  return !fs::is_directory(path) && (path.extension() == ".pcap" || path.extension() == ".pcapng");
}

std::optional<fs::path> FindOusterMetadata(const fs::path& pcap) {
  const fs::path dir = pcap.has_parent_path() ? pcap.parent_path() : fs::path(".");
  const std::string stem = pcap.stem().string();
  std::optional<fs::path> best;
  std::size_t best_length = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const fs::path& p = entry.path();
    if (!entry.is_regular_file() || p.extension() != ".json") continue;
    const std::string s = p.stem().string();
    if (s.size() >= 7 && s.compare(s.size() - 7, 7, "_digest") == 0) continue;
    if (s == stem) return p;
    if (s.size() > best_length && stem.compare(0, s.size(), s) == 0) {
      best = p;
      best_length = s.size();
    }
  }
  return best;
}

std::unique_ptr<io::ScanSource> OpenPcap(const fs::path& pcap, const PcapSourceOptions& o) {
  if (!fs::is_regular_file(pcap)) throw io::IoError(pcap.string() + ": no such file");
  try {
    if (!o.velodyne_model.empty() || !o.velodyne_calibration.empty()) {
      if (o.velodyne_model.empty() || o.velodyne_calibration.empty() || !o.ouster_metadata.empty()) {
        throw std::runtime_error(pcap.string() + ": a Velodyne capture needs both --velodyne-model and "
                                 "--velodyne-calibration (and no --ouster-metadata)");
      }
      return std::make_unique<VelodynePcapSource>(pcap, o.velodyne_model, o.velodyne_calibration);
    }
    if (!o.ouster_metadata.empty()) {
      return std::make_unique<OusterPcapSource>(pcap, o.ouster_metadata, "--ouster-metadata");
    }
    const auto found = FindOusterMetadata(pcap);
    if (!found) {
      throw std::runtime_error(pcap.string() + ": which sensor? Ouster: --ouster-metadata M.json (none found "
                               "beside the capture); Velodyne: --velodyne-model M --velodyne-calibration C.yaml");
    }
    return std::make_unique<OusterPcapSource>(
        pcap, *found, found->stem() == pcap.stem() ? "found beside the capture, same name"
                                                   : "found beside the capture, the longest name prefix");
  } catch (const drivers::DriverError& e) {
    throw io::IoError(e.what());  // the capture, metadata or calibration could not be read
  }
}

}  // namespace dammloam::tools
