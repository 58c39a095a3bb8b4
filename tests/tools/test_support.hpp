#pragma once
#include <filesystem>
#include <functional>
#include <string>

namespace dammloam::test {

// A fresh directory per test (named after the test and the process), removed on destruction,
// so that suites can run in parallel under ctest -j.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// what() of the io::IoError thrown by f, or "<no IoError>" when f returns normally.
std::string IoErrorOf(const std::function<void()>& f);

// The shared real-data folder: $DAMMLOAM_DATA_DIR if set, else the compiled-in default.
std::filesystem::path SharedDataDir();

void WriteText(const std::filesystem::path& file, const std::string& text);
std::string ReadText(const std::filesystem::path& file);

}  // namespace dammloam::test
