#pragma once
#include <filesystem>
#include <vector>

namespace dammloam::io {

// times.txt: one scan start time (seconds) per line, strictly increasing. Blank lines are
// skipped. Errors name the file, the line and the problem.
std::vector<double> ReadTimes(const std::filesystem::path& file);

// Appends one line with the exact text of t.
void AppendTime(const std::filesystem::path& file, double t);

}  // namespace dammloam::io
