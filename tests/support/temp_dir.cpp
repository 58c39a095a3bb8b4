#include "tests/support/temp_dir.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>  // mkdtemp

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace dammloam::test {

namespace {

// "Suite_Test" of the running test ('/' of parameterised names would make a subdirectory).
std::string CurrentTestName() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "test";
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  return name;
}

}  // namespace

TempDir::TempDir(const std::string& tag) {
  const std::string name = "dammloam-" + (tag.empty() ? CurrentTestName() : tag) + "-XXXXXX";
  std::string pattern = (std::filesystem::temp_directory_path() / name).string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    throw std::runtime_error(pattern + ": cannot create a temporary directory: " +
                             std::strerror(errno));
  }
  path_ = pattern;
}

// A destructor cannot fail the test; a directory it cannot remove is at least reported.
TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
  if (ec) std::fprintf(stderr, "%s: cannot remove: %s\n", path_.c_str(), ec.message().c_str());
}

}  // namespace dammloam::test
