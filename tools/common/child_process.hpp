#pragma once
// A tool started as a child process (fork + exec, the caller's environment, so the same
// CYCLONEDDS_URI): its output goes to a log file, or its stdout to a pipe the parent reads.
// Used by the benchmarks and the soak to run dammloamd, dammloam-command and their own
// publisher processes.
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace dammloam::tools {

struct ChildOutput {
  std::filesystem::path log;  // stderr, and stdout unless piped (created or truncated)
  bool pipe_stdout = false;   // stdout to a pipe: ChildProcess::stdout_fd()
};

class ChildProcess {
 public:
  // Starts `exe` with `args` (argv[1..]). Throws std::runtime_error naming `exe` when it cannot.
  // The child gets SIGTERM when the thread that started it ends (PR_SET_PDEATHSIG), so that a
  // killed parent leaves no daemon behind: start children from the main thread.
  ChildProcess(const std::string& exe, const std::vector<std::string>& args,
               const ChildOutput& output);
  // SIGKILL and reap when still running (a child must never outlive its owner unnoticed).
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // The read end of the stdout pipe (owned; closed by the destructor); -1 unless piped.
  int stdout_fd() const { return stdout_fd_; }

  // The exit status once the child ended (exit code, or 128 + signal), nullopt while it runs.
  // Never blocks; reaps the child.
  std::optional<int> ExitStatus();
  // Polls ExitStatus() for up to `timeout`.
  std::optional<int> Wait(std::chrono::milliseconds timeout);
  // Sends `signal_number` unless the child has been reaped.
  void Signal(int signal_number) const;
  // SIGTERM, up to `grace` for the child to end, then SIGKILL; returns the exit status.
  int Terminate(std::chrono::milliseconds grace);

 private:
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::optional<int> exit_status_;
};

// The executable `name` in the directory of the running executable (build/bin).
std::string SiblingExecutable(const std::string& name);
// The running executable itself.
std::string SelfExecutable();

}  // namespace dammloam::tools
