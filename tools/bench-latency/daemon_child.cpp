#include "tools/bench-latency/daemon_child.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <sstream>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace dammloam::bench {

DaemonChild::DaemonChild(std::uint32_t domain, const std::filesystem::path& sensor_meta,
                         const std::string& extra_args, const std::filesystem::path& log) {
  const std::string exe =
      (std::filesystem::read_symlink("/proc/self/exe").parent_path() / "dammloamd").string();
  std::vector<std::string> args = {exe, "--domain", std::to_string(domain), "--sensor-meta",
                                   sensor_meta.string(), "--no-loop-closure", "--log-level",
                                   "warn"};
  std::istringstream extra(extra_args);
  for (std::string a; extra >> a;) args.push_back(a);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  const int rc = posix_spawn(&pid_, exe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + exe);
}

DaemonChild::~DaemonChild() {
  kill(pid_, SIGTERM);
  waitpid(pid_, nullptr, 0);
}

}  // namespace dammloam::bench
