#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace dammloam::io {

// Shortest text that parses back to exactly the same double (std::to_chars round trip).
std::string FormatExact(double value);
std::string FormatExact(float value);

// Parses the whole token as a double (surrounding spaces allowed); nullopt on anything else.
std::optional<double> ParseDouble(std::string_view token);

}  // namespace dammloam::io
