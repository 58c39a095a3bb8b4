#pragma once
#include <functional>
#include <string>

namespace dammloam::test {

// what() of the io::IoError thrown by f, or "<no IoError>" when f returns normally.
std::string IoErrorOf(const std::function<void()>& f);

}  // namespace dammloam::test
