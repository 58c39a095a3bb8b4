#pragma once
// Admission of Command samples (dammloamd.commands): whether a sender may command the daemon at
// all, and which directory a command's argument names. Any participant on the DDS domain can
// write a Command, so nothing runs unless this gate lets it through. No DDS in here: the
// command stage hands over the sender's GUID and the sample's token.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "services/dammloamd/daemon_config.hpp"

namespace dammloam::daemon {

// Refusal reasons, as counted in DaemonStatus.refused_by_reason.
inline constexpr const char* kRefusedDisabled = "disabled";
inline constexpr const char* kRefusedUnknownSender = "unknown_sender";
inline constexpr const char* kRefusedWrongToken = "wrong_token";
inline constexpr const char* kRefusedOutsideRoot = "path_outside_map_root";
inline constexpr const char* kRefusedBadPath = "bad_path";

struct Refusal {
  std::string reason;   // one of the kRefused* codes
  std::string message;  // what the sender is told
};

// Who sent a command and the token it carries.
struct CommandCredentials {
  std::string sender_guid;  // 32 hex digits; empty if the writer is already gone
  std::string token;
};

// A command's directory after resolution: the path to use, or why there is none.
struct ResolvedDirectory {
  std::filesystem::path path;  // absolute, symlinks resolved in the part that exists
  std::optional<Refusal> refusal;
};

// Runs in time that depends only on the length of `expected`: a sender cannot learn from the
// reply's timing how many leading characters of the token it guessed.
bool TokenMatches(std::string_view given, std::string_view expected);

class CommandGate {
 public:
  // Resolves map_root once (it must exist when commands are enabled; the config check says so).
  explicit CommandGate(const CommandsConfig& config);

  // Refuses when commands are disabled, the sender is not on the allow-list or the token is
  // wrong (in that order: a disabled daemon says nothing about its allow-list or token).
  std::optional<Refusal> Admit(const CommandCredentials& credentials) const;

  // `argument` names a directory strictly inside map_root: relative names are taken from
  // map_root, `..` is refused outright, and symlinks in the existing part of the path are
  // resolved before the check, so a link cannot lead outside. A save target that does not exist
  // yet is resolved through its nearest existing ancestor. Guards against remote senders, not
  // local users who can write inside map_root (a link swapped in after the check is not seen).
  ResolvedDirectory Resolve(const std::string& argument) const;

  const std::filesystem::path& map_root() const { return map_root_; }

 private:
  std::optional<Refusal> CheckSender(const std::string& sender_guid) const;

  CommandsConfig config_;
  std::filesystem::path map_root_;  // canonical
};

}  // namespace dammloam::daemon
