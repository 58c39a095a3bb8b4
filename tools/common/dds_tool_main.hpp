#pragma once
#include <spdlog/spdlog.h>

#include <exception>
#include <string>

#include "services/dds/network_guard.hpp"

namespace dammloam::tools {

// The common body of a DDS tool's main(): refuse to start on the default network unless asked
// (exit 2), run, and turn an escaping exception into one error line (exit 1).
template <typename Run>
int RunDdsTool(bool allow_default_network, Run&& run) {
  if (const std::string problem = dds::NetworkConfigProblem(allow_default_network);
      !problem.empty()) {
    spdlog::error("{}", problem);
    return 2;
  }
  try {
    return run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}

}  // namespace dammloam::tools
