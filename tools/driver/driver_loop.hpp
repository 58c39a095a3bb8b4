#pragma once
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "drivers/diagnostics.hpp"
#include "drivers/net/udp_datagram.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "tools/driver/packet_source.hpp"
#include "tools/driver/scan_sink.hpp"

namespace dammloam::driver {

// A sensor's packet decoder seen from the driver loop: datagrams in, complete scans out.
class ScanDecoder {
 public:
  virtual ~ScanDecoder() = default;
  virtual std::optional<Scan> Push(const drivers::UdpDatagram& datagram) = 0;
  virtual void Flush() = 0;
  virtual const drivers::Diagnostics& diagnostics() const = 0;
};

// `dump_range`: every complete frame's staggered range image is appended there (uint32
// little-endian millimetres, beam-major). Throws DriverError if the file cannot be created.
std::unique_ptr<ScanDecoder> MakeOusterDecoder(const drivers::ouster::Metadata& meta,
                                               drivers::ouster::CloudConfig cloud,
                                               const std::optional<std::filesystem::path>& dump_range);
std::unique_ptr<ScanDecoder> MakeVelodyneDecoder(const drivers::velodyne::DecoderConfig& config,
                                                 drivers::velodyne::Calibration calibration);

struct LoopResult {
  std::size_t packets = 0;
  std::size_t scans = 0;
};

// Pumps datagrams from `source` through `decoder` into every sink until the source ends, `stop`
// is set or `max_scans` (0 = unlimited) scans were delivered.
LoopResult RunLoop(PacketSource& source, ScanDecoder& decoder, const std::vector<std::unique_ptr<ScanSink>>& sinks,
                   std::size_t max_scans, const std::atomic<bool>& stop);

}  // namespace dammloam::driver
