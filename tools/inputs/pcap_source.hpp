#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "io/bag/scan_source.hpp"

namespace dammloam::tools {

// A packet capture (.pcap or .pcapng, as libpcap reads it).
bool IsPcapPath(const std::filesystem::path& path);

struct PcapSourceOptions {
  std::filesystem::path ouster_metadata;  // Ouster: the sensor's metadata JSON (empty: look beside)
  std::string velodyne_model;             // Velodyne: vlp16, vlp32c, hdl32e, vls128
  std::filesystem::path velodyne_calibration;
};

// The metadata JSON of an Ouster capture when none is given: beside it, the .json with the same
// stem, else the .json whose stem is the longest prefix of the capture's stem
// (OS-1-128_v2.3.0_1024x10.json for OS-1-128_v2.3.0_1024x10_lb_n3.pcap); *_digest.json files are
// not metadata. Nullopt when there is none.
std::optional<std::filesystem::path> FindOusterMetadata(const std::filesystem::path& pcap);

// Scans from a capture, decoded by drivers/: with a Velodyne model and calibration the 1206-byte
// data packets (any port) through drivers/velodyne (scans cut at azimuth 0, stamps from the
// packets' capture times and their hour timestamps), otherwise the Ouster lidar packets (the
// metadata's UDP port) through drivers/ouster (frames assembled by frame id, stamps and per-point
// times from the column timestamps; incomplete frames dropped). The sensor model is the
// decoder's. A capture that ends inside a record, or holds no complete scan of the sensor, is an
// io::IoError naming the file, the record and the byte offset (or what the capture did hold).
std::unique_ptr<io::ScanSource> OpenPcap(const std::filesystem::path& pcap, const PcapSourceOptions& options);

}  // namespace dammloam::tools
