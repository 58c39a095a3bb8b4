#pragma once
// The soak's publisher process (dammloam-soak --publish-only): publishes simulated scans with
// malformed samples mixed in, on a schedule, and reports every sample it wrote as one line on
// stdout, which the soak's parent reads (SendLedger). It is a process of its own so that the
// parent can SIGKILL it mid-stream: the daemon then sees a writer vanish without disposing.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dammloam::soak {

struct PublisherOptions {
  std::uint32_t domain = 0;
  std::size_t first = 0;  // first scan index to publish
  std::size_t end = 0;    // one past the last
  double rate = 20.0;     // samples per second of wall time (scan k is due (k - first) / rate)
  double malformed_rate = 0.01;
  std::uint64_t seed = 1;
};

// The command line of a publisher process (appended to the soak's own executable).
std::vector<std::string> PublisherArgs(const PublisherOptions& o);

// Waits for dammloamd's reader, publishes scans [first, end), a malformed sample half a period
// after each scan MalformedAfter() names, then waits for the acknowledgements. Exit code 0, or 3
// when no daemon showed up.
int RunPublisher(const PublisherOptions& o);

}  // namespace dammloam::soak
