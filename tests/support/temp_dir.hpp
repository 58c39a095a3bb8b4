#pragma once
#include <filesystem>
#include <string>

namespace dammloam::test {

// A fresh directory "<system temp>/dammloam-<tag>-XXXXXX" (mkdtemp: unique, so suites can run
// in parallel under ctest -j), removed with its contents on destruction, which also runs when
// an ASSERT fails or the test throws. An empty tag names it after the running test.
class TempDir {
 public:
  explicit TempDir(const std::string& tag = "");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace dammloam::test
