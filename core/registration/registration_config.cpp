#include "core/registration/registration_config.hpp"

#include <array>
#include <utility>

namespace dammloam {

namespace {
constexpr std::array<std::pair<RegistrationMode, std::string_view>, 5> kModeNames{{
    {RegistrationMode::kFull, "full"},
    {RegistrationMode::kFullRemap, "full_remap"},
    {RegistrationMode::kPointToPoint, "point_to_point"},
    {RegistrationMode::kPlaneOnly, "plane_only"},
    {RegistrationMode::kClassesNoDegeneracy, "classes_no_degeneracy"},
}};
}  // namespace

std::string_view Name(RegistrationMode mode) {
  for (const auto& [m, name] : kModeNames) {
    if (m == mode) return name;
  }
  return "full";
}

std::optional<RegistrationMode> ParseRegistrationMode(std::string_view name) {
  for (const auto& [m, n] : kModeNames) {
    if (n == name) return m;
  }
  return std::nullopt;
}

}  // namespace dammloam
