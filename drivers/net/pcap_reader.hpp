#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>

#include "drivers/diagnostics.hpp"
#include "drivers/net/link_parser.hpp"
#include "drivers/net/udp_datagram.hpp"

namespace dammloam::drivers {

struct PcapFilter {
  std::optional<std::uint16_t> dst_port;  // only datagrams sent to this port
};

// Reads the UDP datagrams of a capture file (libpcap, classic or pcapng) in file order.
// Non-UDP traffic, other ports and damaged records are skipped and counted.
class PcapReader {
 public:
  // Throws DriverError naming the file when it cannot be opened or has an unknown link type.
  explicit PcapReader(const std::filesystem::path& file, PcapFilter filter = {});
  ~PcapReader();
  PcapReader(const PcapReader&) = delete;
  PcapReader& operator=(const PcapReader&) = delete;

  // Fills `out` with the next matching datagram; false at the end of the file.
  bool Next(UdpDatagram& out);

  // A read error (e.g. a record cut short by the end of the file) is counted as "read_errors"
  // with a message naming the last good record and the byte where it ends.
  const Diagnostics& diagnostics() const { return diag_; }

 private:
  struct Handle;
  std::unique_ptr<Handle> handle_;
  LinkType link_ = LinkType::kEthernet;
  PcapFilter filter_;
  Ipv4Reassembler reassembler_;
  Diagnostics diag_;
  std::uint64_t record_end_ = 0;  // file offset after the last record read (for error messages)
};

}  // namespace dammloam::drivers
