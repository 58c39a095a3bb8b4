#pragma once
#include <cstdio>
#include <string>

namespace dammloam::backend {

// A loop event's reason with two numbers in it ("inlier ratio 0.48 below 0.60").
inline std::string ReasonText(const char* fmt, double a, double b) {
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer), fmt, a, b);
  return buffer;
}

}  // namespace dammloam::backend
