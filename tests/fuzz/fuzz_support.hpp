#pragma once
// Shared by the fuzz targets: reading the fuzz input front to back, per-process scratch files,
// and the seed mode every target has (tools/fuzz.sh runs `fuzz_<name>` with
// DAMMLOAM_FUZZ_SEEDS=<dir> to write its seed corpus, made from ../shared/data captures when
// DAMMLOAM_FUZZ_SHARED_DATA names that folder and from inline/synthetic inputs always).
#include <sanitizer/common_interface_defs.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace dammloam::fuzz {

namespace fs = std::filesystem;

// Reads the input front to back; past the end every value is 0 and every span empty, so any
// input is a valid (if short) sequence of values.
class Input {
 public:
  Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  template <typename T>
  T Get() {
    T value{};
    const std::size_t n = std::min(sizeof(T), remaining());
    std::memcpy(&value, data_ + pos_, n);
    pos_ += n;
    return value;
  }
  std::span<const std::uint8_t> Bytes(std::size_t n) {
    n = std::min(n, remaining());
    std::span<const std::uint8_t> out(data_ + pos_, n);
    pos_ += n;
    return out;
  }
  // Up to (not including) the next NUL byte, which is consumed; the rest when there is none.
  std::string_view UntilNul() {
    const auto* begin = data_ + pos_;
    const auto* nul = static_cast<const std::uint8_t*>(std::memchr(begin, 0, remaining()));
    const std::size_t n = nul != nullptr ? static_cast<std::size_t>(nul - begin) : remaining();
    pos_ += n + (nul != nullptr ? 1 : 0);
    return {reinterpret_cast<const char*>(begin), n};
  }
  std::span<const std::uint8_t> Rest() { return Bytes(remaining()); }
  std::size_t remaining() const { return size_ - pos_; }
  bool empty() const { return pos_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Builds seed inputs in the layout Input reads.
class Bytes {
 public:
  template <typename T>
  Bytes& Put(T value) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    data.insert(data.end(), p, p + sizeof(T));
    return *this;
  }
  Bytes& Append(std::span<const std::uint8_t> bytes) {
    data.insert(data.end(), bytes.begin(), bytes.end());
    return *this;
  }
  Bytes& Append(std::string_view text) {
    data.insert(data.end(), text.begin(), text.end());
    return *this;
  }
  std::vector<std::uint8_t> data;
};

// An invariant of the API broke: a finding, reported like a crash.
// Also written through the sanitizer's report channel, which libFuzzer keeps open when a target
// runs with -close_fd_mask=2 (a noisy third-party library on stderr).
[[noreturn]] inline void Finding(const std::string& what) {
  std::fprintf(stderr, "FUZZ FINDING: %s\n", what.c_str());
  std::fflush(stderr);
  __sanitizer_report_error_summary(("FUZZ FINDING: " + what).c_str());
  std::abort();
}

inline void WriteFile(const fs::path& file, std::span<const std::uint8_t> bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) Finding("cannot write scratch file " + file.string());
}
inline void WriteFile(const fs::path& file, std::string_view text) {
  WriteFile(file, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

inline std::vector<std::uint8_t> ReadFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}
inline std::string ReadText(const fs::path& file) {
  const auto bytes = ReadFile(file);
  return std::string(bytes.begin(), bytes.end());
}

// This process's scratch directory, removed at a normal exit: under DAMMLOAM_FUZZ_SCRATCH
// (tools/fuzz.sh sets it and removes it after the run, so a crash leaves nothing behind), else
// in /dev/shm when there is one (no disk writes per run), else in TMPDIR or /tmp.
inline const fs::path& ScratchDir() {
  static const fs::path dir = [] {
    const char* scratch = std::getenv("DAMMLOAM_FUZZ_SCRATCH");
    const char* tmp = std::getenv("TMPDIR");
    std::string base = scratch != nullptr && *scratch != '\0'                               ? scratch
                       : fs::is_directory("/dev/shm") && ::access("/dev/shm", W_OK) == 0 ? "/dev/shm"
                       : tmp != nullptr                                                  ? tmp
                                                                                         : "/tmp";
    std::string pattern = base + "/dammloam-fuzz-XXXXXX";
    if (::mkdtemp(pattern.data()) == nullptr) Finding("cannot create a scratch directory in " + base);
    static const std::string remove_at_exit = pattern;
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(remove_at_exit, ec);
    });
    return fs::path(pattern);
  }();
  return dir;
}

// Seed mode: when DAMMLOAM_FUZZ_SEEDS is set, `write` is called with that directory (created)
// and the shared data folder (if DAMMLOAM_FUZZ_SHARED_DATA names an existing one), then the
// process exits. Called from LLVMFuzzerInitialize.
template <typename Writer>
void SeedModeIfAsked(Writer write) {
  const char* out = std::getenv("DAMMLOAM_FUZZ_SEEDS");
  if (out == nullptr || *out == '\0') return;
  const fs::path dir(out);
  fs::create_directories(dir);
  std::optional<fs::path> shared;
  if (const char* s = std::getenv("DAMMLOAM_FUZZ_SHARED_DATA"); s != nullptr && fs::is_directory(s)) {
    shared = fs::path(s);
  }
  write(dir, shared);
  std::exit(0);
}

// Seeds are named <name>; a repeated name would overwrite one, so callers use distinct names.
inline void WriteSeed(const fs::path& dir, const std::string& name, std::span<const std::uint8_t> bytes) {
  WriteFile(dir / name, bytes);
}

// The project's source folder (repo config files, calibration files as seeds).
inline fs::path SourceDir() { return fs::path(DAMMLOAM_SOURCE_DIR); }

}  // namespace dammloam::fuzz

// libFuzzer's two entry points for a target: seed mode through `write_seeds`, then every input
// handed to `run` as an Input. One line per target instead of the same two functions in each.
#define DAMMLOAM_FUZZ_TARGET(write_seeds, run)                                       \
  extern "C" int LLVMFuzzerInitialize(int*, char***) {                             \
    ::dammloam::fuzz::SeedModeIfAsked(write_seeds);                                \
    return 0;                                                                      \
  }                                                                                \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    ::dammloam::fuzz::Input in(data, size);                                        \
    run(in);                                                                       \
    return 0;                                                                      \
  }
