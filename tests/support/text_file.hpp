#pragma once
#include <filesystem>
#include <string>

namespace dammloam::test {

// Replaces `file` with `text`, byte for byte.
void WriteText(const std::filesystem::path& file, const std::string& text);
// The whole of `file`, byte for byte; "" when it cannot be read.
std::string ReadText(const std::filesystem::path& file);

}  // namespace dammloam::test
