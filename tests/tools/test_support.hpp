#pragma once
#include <filesystem>
#include <functional>
#include <string>

#include "tests/support/temp_dir.hpp"  // TempDir, used with these helpers

namespace dammloam::test {

// what() of the io::IoError thrown by f, or "<no IoError>" when f returns normally.
std::string IoErrorOf(const std::function<void()>& f);

// The shared real-data folder: $DAMMLOAM_DATA_DIR if set, else the compiled-in default.
std::filesystem::path SharedDataDir();

void WriteText(const std::filesystem::path& file, const std::string& text);
std::string ReadText(const std::filesystem::path& file);

}  // namespace dammloam::test
