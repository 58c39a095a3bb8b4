#include "tools/driver/driver_loop.hpp"

#include <fstream>

#include "drivers/ouster/packet_decoder.hpp"

namespace dammloam::driver {
namespace {

class OusterScanDecoder : public ScanDecoder {
 public:
  OusterScanDecoder(const drivers::ouster::Metadata& meta, drivers::ouster::CloudConfig cloud,
                    const std::optional<std::filesystem::path>& dump_range)
      : decoder_(meta), cloud_(meta, cloud) {
    if (dump_range) {
      dump_.open(*dump_range, std::ios::binary | std::ios::trunc);
      if (!dump_) throw drivers::DriverError("cannot create range dump file " + dump_range->string());
    }
  }
  std::optional<Scan> Push(const drivers::UdpDatagram& d) override {
    auto frame = decoder_.Push(d.payload);
    if (!frame) return std::nullopt;
    if (dump_.is_open()) {
      // The host is little-endian (checked in drivers/bytes.hpp): write the image as is.
      dump_.write(reinterpret_cast<const char*>(frame->range.data()),
                  static_cast<std::streamsize>(frame->range.size() * sizeof(std::uint32_t)));
      dump_.flush();
    }
    Scan scan = cloud_.ToScan(*frame);
    if (scan.empty()) {
      decoder_.diagnostics().Count("empty_frames", "complete frame without a single return; not published");
      return std::nullopt;
    }
    return scan;
  }
  void Flush() override { decoder_.Flush(); }
  const drivers::Diagnostics& diagnostics() const override { return decoder_.diagnostics(); }

 private:
  drivers::ouster::PacketDecoder decoder_;
  drivers::ouster::CloudMaker cloud_;
  std::ofstream dump_;
};

class VelodyneScanDecoder : public ScanDecoder {
 public:
  VelodyneScanDecoder(const drivers::velodyne::DecoderConfig& config, drivers::velodyne::Calibration cal)
      : decoder_(config, std::move(cal)) {}
  std::optional<Scan> Push(const drivers::UdpDatagram& d) override { return decoder_.Push(d.payload, d.capture_time); }
  void Flush() override { decoder_.Flush(); }
  const drivers::Diagnostics& diagnostics() const override { return decoder_.diagnostics(); }

 private:
  drivers::velodyne::Decoder decoder_;
};

}  // namespace

std::unique_ptr<ScanDecoder> MakeOusterDecoder(const drivers::ouster::Metadata& meta, drivers::ouster::CloudConfig cloud,
                                               const std::optional<std::filesystem::path>& dump_range) {
  return std::make_unique<OusterScanDecoder>(meta, cloud, dump_range);
}

std::unique_ptr<ScanDecoder> MakeVelodyneDecoder(const drivers::velodyne::DecoderConfig& config,
                                                 drivers::velodyne::Calibration calibration) {
  return std::make_unique<VelodyneScanDecoder>(config, std::move(calibration));
}

LoopResult RunLoop(PacketSource& source, ScanDecoder& decoder, const std::vector<std::unique_ptr<ScanSink>>& sinks,
                   std::size_t max_scans, const std::atomic<bool>& stop) {
  LoopResult result;
  drivers::UdpDatagram datagram;
  while (!stop && source.Next(datagram, stop)) {
    ++result.packets;
    std::optional<Scan> scan = decoder.Push(datagram);
    if (!scan) continue;
    for (const auto& sink : sinks) sink->Consume(*scan);
    if (++result.scans == max_scans) return result;
  }
  decoder.Flush();
  return result;
}

}  // namespace dammloam::driver
