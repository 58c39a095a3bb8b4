#include "io/mapstore/durable_dir.hpp"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>   // renameat2 (glibc >= 2.28)
#include <stdlib.h>  // mkdtemp
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

namespace dammloam::mapstore {

namespace fs = std::filesystem;

namespace {

constexpr char kStagingTag[] = ".tmp-";
// The previous implementation moved the old map aside under this tag before renaming.
constexpr char kLegacyAsideTag[] = ".old-";

[[noreturn]] void ThrowErrno(const fs::path& path, const std::string& what, int error) {
  throw io::IoError(path.string() + ": " + what + ": " + std::strerror(error));
}

// Owns a file descriptor; Close() reports the error that the destructor has to swallow.
class FileDescriptor {
 public:
  FileDescriptor(const fs::path& path, int flags, const char* what, mode_t mode = 0) {
    do {
      fd_ = ::open(path.c_str(), flags | O_CLOEXEC, mode);
    } while (fd_ < 0 && errno == EINTR);
    if (fd_ < 0) ThrowErrno(path, what, errno);
  }
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }
  // Linux closes the descriptor even when close() fails, so it is never retried.
  void Close(const fs::path& path) {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) ThrowErrno(path, "cannot close", errno);
  }

 private:
  int fd_ = -1;
};

void SyncDescriptor(int fd, const fs::path& path) {
  int result;
  do {
    result = ::fsync(fd);
  } while (result != 0 && errno == EINTR);
  if (result != 0) ThrowErrno(path, "cannot sync to disk", errno);
}

// write() may write less than asked (signals, quotas): loop until done or a real error.
void WriteAll(int fd, const void* data, std::size_t size, const fs::path& path) {
  const auto* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t written = ::write(fd, bytes, size);
    if (written < 0 && errno == EINTR) continue;
    if (written < 0) ThrowErrno(path, "cannot write", errno);
    bytes += written;
    size -= static_cast<std::size_t>(written);
  }
}

// The pid in "<target><tag><pid>-...", if `name` has that form.
std::optional<pid_t> LeftoverPid(const std::string& name, const std::string& prefix) {
  if (name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  const std::size_t dash = name.find('-', prefix.size());
  if (dash == std::string::npos || dash == prefix.size()) return std::nullopt;
  pid_t pid = 0;
  for (std::size_t i = prefix.size(); i < dash; ++i) {
    if (name[i] < '0' || name[i] > '9' || pid > 10'000'000) return std::nullopt;
    pid = pid * 10 + (name[i] - '0');
  }
  return pid > 0 ? std::optional<pid_t>(pid) : std::nullopt;
}

// EPERM means the pid exists (another user's process): alive. A reused pid keeps a left-over
// until a later load; that costs disk space, never a map.
bool ProcessAlive(pid_t pid) { return ::kill(pid, 0) == 0 || errno == EPERM; }

bool IsDeadLeftover(const fs::directory_entry& entry, const std::string& target_name,
                    bool target_present) {
  const std::string name = entry.path().filename().string();
  std::optional<pid_t> pid = LeftoverPid(name, target_name + kStagingTag);
  // An aside copy of the legacy scheme is the only complete map while the target is missing.
  if (!pid && target_present) pid = LeftoverPid(name, target_name + kLegacyAsideTag);
  if (!pid || ProcessAlive(*pid)) return false;
  std::error_code ec;
  const fs::file_status status = entry.symlink_status(ec);
  return !ec && (fs::is_directory(status) || fs::is_symlink(status));
}

}  // namespace

void WriteFileDurably(const fs::path& file, const void* data, std::size_t size) {
  FileDescriptor fd(file, O_WRONLY | O_CREAT | O_TRUNC, "cannot create", 0644);
  WriteAll(fd.get(), data, size, file);
  SyncDescriptor(fd.get(), file);
  fd.Close(file);
}

void SyncPath(const fs::path& path) {
  FileDescriptor fd(path, O_RDONLY, "cannot open to sync");
  SyncDescriptor(fd.get(), path);
  fd.Close(path);
}

void CreateParentsDurably(const fs::path& dir) {
  const fs::path parent = dir.parent_path();
  std::error_code ec;
  if (parent.empty() || parent == dir || fs::is_directory(parent, ec)) return;
  CreateParentsDurably(parent);
  if (::mkdir(parent.c_str(), 0755) != 0 && errno != EEXIST) {
    ThrowErrno(parent, "cannot create directory", errno);
  }
  SyncPath(parent.parent_path());
}

fs::path MakeStagingSibling(const fs::path& target) {
  std::string pattern = target.string() + kStagingTag + std::to_string(::getpid()) + "-XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) {
    ThrowErrno(target.parent_path(),
               "cannot create a staging directory for " + target.filename().string(), errno);
  }
  return pattern;
}

void PublishStaging(const fs::path& staging, const fs::path& target) {
  std::error_code ec;
  const bool replacing = fs::symlink_status(target, ec).type() != fs::file_type::not_found;
  const unsigned flags = replacing ? RENAME_EXCHANGE : RENAME_NOREPLACE;
  if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, target.c_str(), flags) != 0) {
    const int error = errno;
    if (replacing && error == EINVAL) {
      ThrowErrno(target, "cannot replace the map atomically (this file system lacks renameat2 "
                         "RENAME_EXCHANGE; the existing map is unchanged)", error);
    }
    ThrowErrno(target, "cannot move the new map into place (the existing map is unchanged)",
               error);
  }
  SyncPath(target.parent_path());
}

std::size_t RemoveInterruptedSaves(const fs::path& target) {
  std::error_code ec;
  const bool target_present = fs::is_directory(target, ec);
  const std::string target_name = target.filename().string();
  std::vector<fs::path> leftovers;  // collected first: no removal while the directory is read
  fs::directory_iterator it(target.parent_path(), ec);
  for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
    if (IsDeadLeftover(*it, target_name, target_present)) leftovers.push_back(it->path());
  }
  std::size_t removed = 0;
  for (const fs::path& leftover : leftovers) {
    std::error_code remove_ec;
    fs::remove_all(leftover, remove_ec);
    if (!remove_ec) ++removed;
  }
  return removed;
}

}  // namespace dammloam::mapstore
