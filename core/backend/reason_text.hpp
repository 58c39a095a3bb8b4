#pragma once
#include <cstdio>
#include <string>

namespace dammloam::backend {

// A loop event's reason with numbers in it ("inlier ratio 0.48 below 0.60").
template <typename... Numbers>
std::string ReasonText(const char* fmt, Numbers... numbers) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), fmt, static_cast<double>(numbers)...);
  return buffer;
}

}  // namespace dammloam::backend
