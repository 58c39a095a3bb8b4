#pragma once
#include <functional>
#include <initializer_list>
#include <string>

namespace dammloam::test {

// what() of the io::IoError thrown by f, or "<no IoError>" when f returns normally.
std::string IoErrorOf(const std::function<void()>& f);

// Expects an IoError mentioning every fragment.
#define EXPECT_IO_ERROR(statement, ...)                                                    \
  do {                                                                                     \
    const std::string error_ = ::dammloam::test::IoErrorOf([&] { statement; });           \
    for (const std::string& fragment_ : std::initializer_list<std::string>{__VA_ARGS__}) { \
      EXPECT_NE(error_.find(fragment_), std::string::npos)                                 \
          << "missing '" << fragment_ << "' in: " << error_;                               \
    }                                                                                      \
  } while (false)

}  // namespace dammloam::test
