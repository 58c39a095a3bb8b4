#include "tools/common/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace dammloam::tools {
namespace {

int StatusCode(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

[[noreturn]] void Fail(const std::string& what, int error) {
  throw std::runtime_error(what + ": " + std::strerror(error));
}

// In the forked child: only async-signal-safe calls until exec (the parent has threads).
[[noreturn]] void ExecChild(pid_t parent, int log_fd, int stdout_fd, char* const* argv) {
  // A parent killed without cleaning up (a test timeout) takes its children with it: SIGTERM
  // lets a daemon stop cleanly. Sent when the forking thread ends, so fork on the main thread.
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
  dup2(log_fd, 2);
  dup2(stdout_fd, 1);
  execve(argv[0], argv, environ);
  _exit(127);
}

}  // namespace

ChildProcess::ChildProcess(const std::string& exe, const std::vector<std::string>& args,
                           const ChildOutput& output) {
  if (access(exe.c_str(), X_OK) != 0) Fail("cannot start " + exe, errno);
  std::vector<std::string> argv_storage{exe};
  argv_storage.insert(argv_storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_storage) argv.push_back(a.data());
  argv.push_back(nullptr);

  // Opened here, not in the child, so that every failure is the parent's exception. O_CLOEXEC:
  // no other child inherits them (dup2 onto fds 1 and 2 clears the flag for this one).
  const int log_fd = open(output.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log_fd < 0) Fail("cannot open " + output.log.string(), errno);
  int pipe_fds[2] = {-1, -1};
  if (output.pipe_stdout && pipe2(pipe_fds, O_CLOEXEC) != 0) {
    const int error = errno;
    close(log_fd);
    Fail("cannot create a pipe for " + exe, error);
  }
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ == 0) ExecChild(parent, log_fd, output.pipe_stdout ? pipe_fds[1] : log_fd, argv.data());
  const int fork_error = errno;
  close(log_fd);
  if (pipe_fds[1] >= 0) close(pipe_fds[1]);  // the child holds the write end now
  if (pid_ < 0) {
    if (pipe_fds[0] >= 0) close(pipe_fds[0]);
    Fail("cannot start " + exe, fork_error);
  }
  stdout_fd_ = pipe_fds[0];
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !exit_status_) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  if (stdout_fd_ >= 0) close(stdout_fd_);
}

std::optional<int> ChildProcess::ExitStatus() {
  if (exit_status_ || pid_ <= 0) return exit_status_;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) exit_status_ = StatusCode(status);
  return exit_status_;
}

std::optional<int> ChildProcess::Wait(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!ExitStatus() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return exit_status_;
}

void ChildProcess::Signal(int signal_number) const {
  if (pid_ > 0 && !exit_status_) kill(pid_, signal_number);
}

int ChildProcess::Terminate(std::chrono::milliseconds grace) {
  Signal(SIGTERM);
  if (const auto status = Wait(grace)) return *status;
  Signal(SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  exit_status_ = StatusCode(status);
  return *exit_status_;
}

std::string SelfExecutable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

std::string SiblingExecutable(const std::string& name) {
  return (std::filesystem::path(SelfExecutable()).parent_path() / name).string();
}

}  // namespace dammloam::tools
