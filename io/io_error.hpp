#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>

namespace dammloam::io {

// Every file problem (missing, malformed, inconsistent) is reported with this type; the message
// always names the file (and line or point index where it helps) and what is wrong.
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "FILE: problem".
[[noreturn]] inline void FailIn(const std::filesystem::path& file, const std::string& problem) {
  throw IoError(file.string() + ": " + problem);
}

}  // namespace dammloam::io
