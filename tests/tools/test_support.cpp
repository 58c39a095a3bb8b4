#include "tests/tools/test_support.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/io_error.hpp"

namespace dammloam::test {

std::string IoErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const io::IoError& e) {
    return e.what();
  }
  return "<no IoError>";
}

std::filesystem::path SharedDataDir() {
  if (const char* env = std::getenv("DAMMLOAM_DATA_DIR"); env && *env) return env;
  return DAMMLOAM_SHARED_DATA_DIR;
}

void WriteText(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
}

std::string ReadText(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace dammloam::test
