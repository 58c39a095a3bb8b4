#include "tests/tools/test_support.hpp"

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

}  // namespace dammloam::test
