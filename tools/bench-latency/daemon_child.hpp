#pragma once
// dammloamd as a child process of the benchmark, so that every run starts from an empty map.
#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace dammloam::bench {

class DaemonChild {
 public:
  // Starts the dammloamd next to this executable on `domain` with `sensor_meta` as its
  // --sensor-meta, no loop closure, and `extra_args` (whitespace-separated) appended. Its stdout
  // and stderr (drop warnings, errors) go to `log`, never into the caller's directories.
  DaemonChild(std::uint32_t domain, const std::filesystem::path& sensor_meta,
              const std::string& extra_args, const std::filesystem::path& log);
  // SIGTERM, then waits for the exit.
  ~DaemonChild();
  DaemonChild(const DaemonChild&) = delete;
  DaemonChild& operator=(const DaemonChild&) = delete;

 private:
  pid_t pid_ = -1;
};

}  // namespace dammloam::bench
