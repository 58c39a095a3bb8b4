#pragma once
// The soak's verdict, its printed report and its JSON file.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "tools/soak/soak_run.hpp"

namespace dammloam::soak {

// One rejection code: the malformed samples sent that the daemon must reject with it, against
// its "rejected:<code>" counter. Codes the daemon counted without a sample sent for them (a
// valid scan rejected) are listed with expected 0.
struct RejectionCheck {
  std::string code;
  std::vector<std::string> kinds;  // the malformed kinds that map to it
  std::uint64_t expected = 0, counted = 0;
  bool ok() const { return expected == counted; }
};
std::vector<RejectionCheck> CheckRejections(const SoakResult& r);

// Why the run failed, one line each; empty: it passed. Drops and latency are reported, never
// failed on: the machine's load decides them, not the daemon alone.
std::vector<std::string> Failures(const SoakResult& r, const SoakOptions& o);

void PrintReport(const SoakResult& r, const SoakOptions& o,
                 const std::vector<std::string>& failures);
nlohmann::json ToJson(const SoakResult& r, const SoakOptions& o,
                      const std::vector<std::string>& failures);

}  // namespace dammloam::soak
