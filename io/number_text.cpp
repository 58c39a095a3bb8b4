#include "io/number_text.hpp"

#include <array>
#include <charconv>

namespace dammloam::io {

std::string FormatExact(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string FormatExact(float value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::optional<double> ParseDouble(std::string_view token) {
  const auto first = token.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return std::nullopt;
  token.remove_prefix(first);
  token.remove_suffix(token.size() - token.find_last_not_of(" \t\r") - 1);
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0.0;
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  if (result.ec != std::errc() || result.ptr != token.data() + token.size()) return std::nullopt;
  return value;
}

}  // namespace dammloam::io
