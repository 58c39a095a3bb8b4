#include "drivers/net/pcap_reader.hpp"

#include <pcap/pcap.h>

#include <cstdio>
#include <span>
#include <string>

namespace dammloam::drivers {

struct PcapReader::Handle {
  pcap_t* pcap = nullptr;
  ~Handle() {
    if (pcap != nullptr) pcap_close(pcap);
  }
};

PcapReader::PcapReader(const std::filesystem::path& file, PcapFilter filter)
    : handle_(std::make_unique<Handle>()), filter_(filter) {
  char err[PCAP_ERRBUF_SIZE] = {0};
  handle_->pcap = pcap_open_offline(file.c_str(), err);
  if (handle_->pcap == nullptr) {
    throw DriverError("cannot read capture " + file.string() + ": " + err);
  }
  const int dlt = pcap_datalink(handle_->pcap);
  switch (dlt) {
    case DLT_EN10MB: link_ = LinkType::kEthernet; break;
    case DLT_LINUX_SLL: link_ = LinkType::kLinuxSll; break;
    case DLT_NULL: link_ = LinkType::kNull; break;
    case DLT_RAW:
    case 101: link_ = LinkType::kRawIp; break;
    default:
      throw DriverError("capture " + file.string() + ": unsupported link type " +
                        std::to_string(dlt) + " (need Ethernet, Linux SLL, BSD loopback or raw IP)");
  }
}

PcapReader::~PcapReader() = default;

bool PcapReader::Next(UdpDatagram& out) {
  for (;;) {
    pcap_pkthdr* header = nullptr;
    const std::uint8_t* data = nullptr;
    const int rc = pcap_next_ex(handle_->pcap, &header, &data);
    if (rc == PCAP_ERROR_BREAK) return false;
    if (rc != 1) {
      // A record cut short by the end of the file is the usual cause.
      diag_.Count("read_errors", "pcap read stopped after record " + std::to_string(diag_.Get("records")) +
                                     " (which ends at byte " + std::to_string(record_end_) +
                                     "): " + pcap_geterr(handle_->pcap));
      return false;
    }
    diag_.Count("records");
    if (FILE* f = pcap_file(handle_->pcap); f != nullptr) {
      const long at = std::ftell(f);
      if (at >= 0) record_end_ = static_cast<std::uint64_t>(at);
    }
    if (header->caplen < header->len) {
      diag_.Count("truncated_records", "capture record shorter than the packet on the wire");
      continue;
    }
    if (!ParseLinkFrame(link_, std::span(data, header->caplen), reassembler_, out, diag_)) continue;
    if (filter_.dst_port && out.dst_port != *filter_.dst_port) {
      diag_.Count("other_ports");
      continue;
    }
    out.capture_time = static_cast<double>(header->ts.tv_sec) + 1e-6 * static_cast<double>(header->ts.tv_usec);
    diag_.Count("datagrams");
    return true;
  }
}

}  // namespace dammloam::drivers
