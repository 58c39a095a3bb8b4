#pragma once
// Printed rows and the optional JSON file of dammloam-bench-latency.
#include <nlohmann/json.hpp>

#include <string>

#include "tools/bench-latency/latency_run.hpp"

namespace dammloam::bench {

// "rate  10.0 Hz: 99/100 poses, latency median ..., core median ... ms/scan  (DROPS)", plus a
// note when publishes missed their instant.
void PrintRateRow(const RunResult& r);
// The drop lines of a sequence run: ours (sent - received) and the daemon's own Status counters.
void PrintDrops(const RunResult& r);

nlohmann::json ToJson(const RunResult& r);
// Writes atomically (temporary file, then rename); throws naming the file when it cannot.
void WriteJson(const std::string& path, const nlohmann::json& report);

// Peak resident set of this process (VmHWM) in MiB; 0 where unavailable.
double PeakResidentMiB();

}  // namespace dammloam::bench
