#include "services/dammloamd/command_gate.hpp"

#include <algorithm>
#include <cctype>
#include <system_error>

namespace dammloam::daemon {
namespace {

namespace fs = std::filesystem;

bool StartsWithHex(const std::string& guid, const std::string& prefix) {
  if (prefix.size() > guid.size()) return false;
  return std::equal(prefix.begin(), prefix.end(), guid.begin(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
  });
}

bool HasDotDot(const fs::path& path) {
  return std::any_of(path.begin(), path.end(), [](const fs::path& part) { return part == ".."; });
}

// `inner` is `root` or below it, compared component by component (so /maps2 is not in /maps).
bool IsStrictlyInside(const fs::path& inner, const fs::path& root) {
  const auto [root_end, inner_at] = std::mismatch(root.begin(), root.end(), inner.begin(), inner.end());
  return root_end == root.end() && inner_at != inner.end();
}

// Splits an absolute, normalised path into its longest leading part that exists (anything that
// is there counts, a dangling symlink too) and the rest.
std::pair<fs::path, fs::path> SplitAtFirstMissing(const fs::path& path) {
  fs::path existing, rest;
  for (const fs::path& part : path) {
    std::error_code ec;
    if (rest.empty() && fs::symlink_status(existing / part, ec).type() != fs::file_type::not_found &&
        !ec) {
      existing /= part;
    } else {
      rest /= part;
    }
  }
  return {existing, rest};
}

Refusal Outside(const std::string& argument, const fs::path& resolved, const fs::path& root) {
  return {kRefusedOutsideRoot, "'" + argument + "' resolves to " + resolved.string() +
                                   ", which is not inside the map root " + root.string()};
}

}  // namespace

bool TokenMatches(std::string_view given, std::string_view expected) {
  // Every byte of `expected` is visited and differences are OR-ed, never branched on.
  unsigned difference = given.size() == expected.size() ? 0u : 1u;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const unsigned char g = i < given.size() ? static_cast<unsigned char>(given[i]) : 0u;
    difference |= g ^ static_cast<unsigned char>(expected[i]);
  }
  return difference == 0;
}

CommandGate::CommandGate(const CommandsConfig& config) : config_(config) {
  if (config.enabled) map_root_ = fs::canonical(config.map_root);
}

std::optional<Refusal> CommandGate::Admit(const CommandCredentials& credentials) const {
  if (!config_.enabled) {
    return Refusal{kRefusedDisabled, "commands are disabled on this daemon "
                                     "(dammloamd.commands.enabled is false)"};
  }
  if (auto refusal = CheckSender(credentials.sender_guid)) return refusal;
  if (!config_.token.empty() && !TokenMatches(credentials.token, config_.token)) {
    return Refusal{kRefusedWrongToken, credentials.token.empty()
                                           ? "this daemon requires a command token"
                                           : "wrong command token"};
  }
  return std::nullopt;
}

std::optional<Refusal> CommandGate::CheckSender(const std::string& sender_guid) const {
  if (config_.allowed_participants.empty()) return std::nullopt;
  for (const std::string& prefix : config_.allowed_participants) {
    if (!sender_guid.empty() && StartsWithHex(sender_guid, prefix)) return std::nullopt;
  }
  return Refusal{kRefusedUnknownSender,
                 "participant " + (sender_guid.empty() ? std::string("<unknown>") : sender_guid) +
                     " is not in dammloamd.commands.allowed_participants"};
}

ResolvedDirectory CommandGate::Resolve(const std::string& argument) const {
  if (argument.empty()) return {{}, Refusal{kRefusedBadPath, "no directory given"}};
  const fs::path given(argument);
  if (HasDotDot(given)) {
    return {{}, Refusal{kRefusedOutsideRoot, "'" + argument + "': '..' is not allowed in "
                                             "command paths (map root " + map_root_.string() + ")"}};
  }
  fs::path absolute = (given.is_absolute() ? given : map_root_ / given).lexically_normal();
  if (!absolute.has_filename()) absolute = absolute.parent_path();  // "run1/" names run1
  const auto [existing, rest] = SplitAtFirstMissing(absolute);
  std::error_code ec;
  const fs::path real = fs::canonical(existing, ec);
  if (ec) {  // a dangling symlink or an unreadable directory on the way
    return {{}, Refusal{kRefusedBadPath, "cannot resolve '" + argument + "' (" +
                                             existing.string() + ": " + ec.message() + ")"}};
  }
  const fs::path resolved = rest.empty() ? real : real / rest;
  if (!IsStrictlyInside(resolved, map_root_)) return {{}, Outside(argument, resolved, map_root_)};
  return {resolved, std::nullopt};
}

}  // namespace dammloam::daemon
