#pragma once
// What the packet inputs (captures, bags of raw packets) share: Ouster frames made into scans,
// and the Velodyne decoder's configuration from --velodyne-model.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "core/geometry/scan.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/metadata.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "drivers/velodyne/decoder.hpp"

namespace dammloam::tools {

// Ouster lidar packets in, a scan out per complete frame that holds a return.
class OusterScans {
 public:
  explicit OusterScans(const drivers::ouster::Metadata& meta) : decoder_(meta), cloud_(meta) {}
  std::optional<Scan> Push(std::span<const std::uint8_t> packet) {
    auto frame = decoder_.Push(packet);
    if (!frame) return std::nullopt;
    Scan scan = cloud_.ToScan(*frame);
    if (scan.empty()) return std::nullopt;
    ++scans_;
    return scan;
  }
  void Flush() { decoder_.Flush(); }
  std::size_t scans() const { return scans_; }
  const drivers::Diagnostics& diagnostics() const { return decoder_.diagnostics(); }

 private:
  drivers::ouster::PacketDecoder decoder_;
  drivers::ouster::CloudMaker cloud_;
  std::size_t scans_ = 0;
};

inline drivers::velodyne::DecoderConfig VelodyneDecoderConfig(const std::string& model) {
  const auto parsed = drivers::velodyne::ParseModel(model);
  if (!parsed) {
    throw std::runtime_error("--velodyne-model '" + model + "': expected vlp16, vlp32c, hdl32e or vls128");
  }
  drivers::velodyne::DecoderConfig config;
  config.model = *parsed;
  return config;
}

}  // namespace dammloam::tools
