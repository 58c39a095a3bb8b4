#pragma once
// The malformed samples the soak mixes into its stream: their kinds, where they go, and the code
// dammloamd must reject each with (DaemonStatus.rejected_by_reason "rejected:<code>").
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "services/dds/point_cloud.hpp"

namespace dammloam::soak {

// dammloamd.input.max_cloud_bytes of the soak's daemon: a VLP-16 scan (14,400 points x 24 bytes
// at 20 Hz, twice that at 10 Hz) fits, the oversized kind (1.5 MiB) does not.
inline constexpr std::uint64_t kMaxCloudBytes = 1u << 20;

struct MalformedKind {
  std::string name;  // as reported: nan_point, empty_cloud, ...
  std::string code;  // the daemon's rejection code for it
};

// Every kind, in the order the stream cycles through them.
const std::vector<MalformedKind>& MalformedKinds();

// The kind (index into MalformedKinds()) of the malformed sample that follows valid scan `scan`,
// or nullopt. A fraction `rate` of the scans is followed by one, evenly spaced, the kinds in
// turn. A function of the scan index only, so that a restarted publisher keeps the schedule.
std::optional<std::size_t> MalformedAfter(std::size_t scan, double rate);

// A copy of `valid` (the scan just sent) broken as `kind` says.
dds::CloudMessage MakeMalformed(std::size_t kind, const dds::CloudMessage& valid);

}  // namespace dammloam::soak
