#include "tools/inputs/scan_input.hpp"

#include <algorithm>
#include <spdlog/spdlog.h>

#include "io/bag/bag_reader.hpp"
#include "tools/inputs/ouster_bag_source.hpp"
#include "tools/inputs/pcap_source.hpp"
#include "tools/inputs/velodyne_bag_source.hpp"

namespace dammloam::tools {

std::unique_ptr<io::ScanSource> OpenScanInput(const ScanInputOptions& o) {
  if (IsPcapPath(o.path)) {
    if (!o.topic.empty() || !o.sensor_meta.empty() || o.scan_period > 0.0) {
      throw std::runtime_error(o.path.string() + ": --topic, --sensor-meta and --scan-period are not "
                               "for captures (the decoder gives the sensor model and the stamps)");
    }
    auto source = OpenPcap(o.path, {o.ouster_metadata, o.velodyne_model, o.velodyne_calibration});
    if (!o.quiet) spdlog::info("{}: {}", o.path.string(), source->Describe());
    return source;
  }
  if (!o.ouster_metadata.empty()) {
    if (!io::IsBagPath(o.path)) {
      throw std::runtime_error("--ouster-metadata is for Ouster captures (.pcap) and bags of Ouster packets");
    }
    auto source = OpenOusterBag(o.path, o.topic, o.ouster_metadata);
    if (!o.quiet) spdlog::info("{}: {}", o.path.string(), source->Describe());
    return source;
  }
  if (!o.velodyne_model.empty() || !o.velodyne_calibration.empty()) {
    if (o.velodyne_model.empty() || o.velodyne_calibration.empty() || !io::IsBagPath(o.path)) {
      throw std::runtime_error("raw Velodyne packets need a bag or a .pcap and both "
                               "--velodyne-model and --velodyne-calibration");
    }
    return OpenVelodyneBag(o.path, o.topic, o.velodyne_model, o.velodyne_calibration);
  }
  std::unique_ptr<io::ScanSource> source;
  try {
    source = io::OpenScanSource(o.path, {o.topic, o.sensor_meta, o.scan_period});
  } catch (const io::IoError& e) {
    if (io::IsBagPath(o.path) && HasOusterPackets(o.path)) {
      throw io::IoError(std::string(e.what()) + "; for its Ouster packets give the sensor's metadata: "
                        "--ouster-metadata FILE.json");
    }
    throw;
  }
  if (source->kind() == "sequence" && (!o.topic.empty() || !o.sensor_meta.empty() || o.scan_period > 0.0)) {
    throw std::runtime_error(o.path.string() + ": --topic, --sensor-meta and --scan-period are for "
                             "bags and cloud folders; a sequence directory has its own meta.json");
  }
  if (source->kind() == "cloud folder" && !o.topic.empty()) {
    throw std::runtime_error(o.path.string() + ": --topic is for bags, not a folder of clouds");
  }
  if (!o.quiet && !source->Describe().empty()) {
    spdlog::info("{}: {}", o.path.string(), source->Describe());
  }
  if (source->kind() == "cloud folder" && o.sensor_meta.empty() &&
      source->Describe().find("no beams found") != std::string::npos) {
    // Without rings or beams nothing tells the beam count: the guess keeps the default 64 rings,
    // and the range image (normals, classes) of another sensor is then wrong (the HDL-32E pair of
    // ../shared/data registers 38 cm off that way instead of 3 cm).
    spdlog::warn("{}: the clouds have no ring field and no beams were found in their elevations; "
                 "give --sensor-meta meta.json (rings, columns, scan_period, vertical_angles_deg)",
                 o.path.string());
  }
  if (!o.quiet && source->kind() != "sequence" && o.sensor_meta.empty()) {
    const SensorModel& m = source->model();
    spdlog::info("{}: sensor model guessed from the first clouds: {} rings, {} columns, {:.3f} s "
                 "per scan (give --sensor-meta meta.json to set it)",
                 o.path.string(), m.rings, m.columns, m.scan_period);
  }
  return source;
}

std::size_t ScansToRun(const io::ScanSource& source, std::size_t max_scans) {
  const std::optional<std::size_t> size = source.size();
  if (!size) return max_scans;
  return max_scans > 0 ? std::min(max_scans, *size) : *size;
}

}  // namespace dammloam::tools
