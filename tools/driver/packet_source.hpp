#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "drivers/diagnostics.hpp"
#include "drivers/net/udp_datagram.hpp"

namespace dammloam::driver {

struct SourceOptions {
  std::optional<std::filesystem::path> pcap;  // replay a capture...
  std::optional<std::uint16_t> udp_port;      // ...or listen live
  std::uint16_t sensor_port = 0;              // pcap: only datagrams to this port
  std::string bind_address = "0.0.0.0";
  double rate = 0.0;                          // pcap replay speed; 0 = as fast as possible
  double idle_timeout_s = 0.0;                // live: stop after this long without data; 0 = never
};

// UDP payloads from a capture (optionally paced at the recorded rate) or a live socket.
class PacketSource {
 public:
  virtual ~PacketSource() = default;
  // Next datagram; false at the end of the capture, on idle timeout or when `stop` is set.
  virtual bool Next(drivers::UdpDatagram& out, const std::atomic<bool>& stop) = 0;
  virtual const drivers::Diagnostics* diagnostics() const { return nullptr; }
  virtual std::string Describe() const = 0;
};

// Throws drivers::DriverError when the capture cannot be opened or the port cannot be bound.
std::unique_ptr<PacketSource> MakeSource(const SourceOptions& options);

}  // namespace dammloam::driver
