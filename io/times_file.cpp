#include "io/times_file.hpp"

#include <cmath>
#include <fstream>
#include <string>

#include "io/io_error.hpp"
#include "io/number_text.hpp"

namespace dammloam::io {

std::vector<double> ReadTimes(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw IoError(file.string() + ": cannot open (missing times.txt?)");
  std::vector<double> times;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = file.string() + ":" + std::to_string(line) + ": ";
    const auto t = ParseDouble(text);
    if (!t || !std::isfinite(*t)) throw IoError(where + "'" + text + "' is not a time in seconds");
    if (!times.empty() && !(*t > times.back())) {
      throw IoError(where + "time " + FormatExact(*t) + " is not greater than the previous " +
                    FormatExact(times.back()) + " (times must be strictly increasing)");
    }
    times.push_back(*t);
  }
  return times;
}

void AppendTime(const std::filesystem::path& file, double t) {
  std::ofstream out(file, std::ios::app);
  out << FormatExact(t) << '\n';
  if (!out) throw IoError(file.string() + ": cannot append to times file");
}

}  // namespace dammloam::io
