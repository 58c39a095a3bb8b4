#pragma once
// The line a publisher process writes on stdout for every sample it handed to DDS, and its
// parser in the soak's parent.
#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

#include "dammloam.h"

namespace dammloam::soak {

inline constexpr const char* kScanKind = "scan";  // a valid scan; otherwise a MalformedKind name

struct SentSample {
  std::size_t scan = 0;   // the scan it is (or follows, for a malformed sample)
  std::string kind;
  dammloam_msg_Time stamp{};
  // steady_clock (CLOCK_MONOTONIC, the same in every process of the machine) since its epoch.
  std::chrono::nanoseconds due{0}, sent{0};
};

// "sent SCAN KIND SEC NANOSEC DUE_NS SENT_NS\n"
std::string FormatSent(const SentSample& s);
// nullopt for any other line.
std::optional<SentSample> ParseSent(const std::string& line);

}  // namespace dammloam::soak
