#pragma once
// dammloamd as a child process of the benchmark, so that every run starts from an empty map.
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "tools/common/child_process.hpp"

namespace dammloam::bench {

// Latency runs measure the odometry path alone; a soak runs the daemon as deployed.
enum class LoopClosure { kOff, kOn };

class DaemonChild {
 public:
  // Starts the dammloamd next to this executable on `domain` with `sensor_meta` as its
  // --sensor-meta, loop closure as asked, and `extra_args` (whitespace-separated) appended. Its
  // stdout and stderr (drop warnings, errors) go to `log`, never into the caller's directories.
  DaemonChild(std::uint32_t domain, const std::filesystem::path& sensor_meta,
              const std::string& extra_args, const std::filesystem::path& log,
              LoopClosure loop_closure = LoopClosure::kOff);
  // Stop() unless it already ended.
  ~DaemonChild();
  DaemonChild(const DaemonChild&) = delete;
  DaemonChild& operator=(const DaemonChild&) = delete;

  pid_t pid() const { return process_.pid(); }
  // The exit status once the daemon ended (exit code, or 128 + signal); nullopt while it runs.
  std::optional<int> ExitStatus() { return process_.ExitStatus(); }
  // SIGTERM, then waits up to `grace` (a shutdown save takes seconds) before SIGKILL; returns
  // the exit status (0: a clean stop).
  int Stop(std::chrono::milliseconds grace = std::chrono::seconds(60)) {
    return process_.Terminate(grace);
  }

 private:
  tools::ChildProcess process_;
};

}  // namespace dammloam::bench
