#include "tools/bench-latency/daemon_child.hpp"

#include <sstream>
#include <vector>

namespace dammloam::bench {
namespace {

std::vector<std::string> DaemonArgs(std::uint32_t domain, const std::filesystem::path& sensor_meta,
                                    const std::string& extra_args, LoopClosure loop_closure) {
  std::vector<std::string> args = {"--domain", std::to_string(domain), "--sensor-meta",
                                   sensor_meta.string(), "--log-level", "warn"};
  if (loop_closure == LoopClosure::kOff) args.push_back("--no-loop-closure");
  std::istringstream extra(extra_args);
  for (std::string a; extra >> a;) args.push_back(a);
  return args;
}

}  // namespace

DaemonChild::DaemonChild(std::uint32_t domain, const std::filesystem::path& sensor_meta,
                         const std::string& extra_args, const std::filesystem::path& log,
                         LoopClosure loop_closure)
    : process_(tools::SiblingExecutable("dammloamd"),
               DaemonArgs(domain, sensor_meta, extra_args, loop_closure), {log, false}) {}

DaemonChild::~DaemonChild() {
  if (!process_.ExitStatus()) Stop();
}

}  // namespace dammloam::bench
