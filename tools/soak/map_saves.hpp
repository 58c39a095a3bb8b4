#pragma once
// The soak's save_map commands (dammloam-command as a child process, so the command path is
// the one operators use) and the check that every saved map loads with io/mapstore.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tools/common/child_process.hpp"

namespace dammloam::soak {

struct SaveRecord {
  std::string name;             // directory under the map root
  std::size_t after_scans = 0;  // valid scans sent when it was requested; 0: shutdown save
  std::optional<int> command_exit;  // dammloam-command's exit code (0: the daemon saved it)
  double command_seconds = 0.0;     // request -> reply
  std::string reply;                // the daemon's reply as dammloam-command printed it
  bool loaded = false;
  std::string load_error;
  std::size_t keyframes = 0, loops = 0, map_points = 0;
  bool ok() const { return (after_scans == 0 || command_exit == 0) && loaded; }
};

class MapSaves {
 public:
  // Commands go to the daemon on `domain`; map directories live in `map_root` (the daemon's
  // dammloamd.commands.map_root), command logs in `log_dir`.
  MapSaves(std::uint32_t domain, std::filesystem::path map_root, std::filesystem::path log_dir);

  // Starts `dammloam-command save_map save-NNNNNN` without waiting for it.
  void Request(std::size_t after_scans);
  // Notes the commands that finished. Never blocks.
  void Reap();
  bool AllAnswered() const;
  // The daemon's save_map_on_shutdown directory, checked like the others.
  void AddShutdownSave(const std::string& name);
  // Loads every map whose command succeeded (and the shutdown save) with mapstore::LoadMap.
  void LoadAll();

  const std::vector<SaveRecord>& records() const { return records_; }

 private:
  struct Running {
    std::size_t record;
    std::unique_ptr<tools::ChildProcess> process;
    std::chrono::steady_clock::time_point started;
    std::filesystem::path log;
  };
  void Finish(Running& running, int exit_code);

  std::uint32_t domain_;
  std::filesystem::path map_root_, log_dir_;
  std::vector<SaveRecord> records_;
  std::vector<Running> running_;
};

}  // namespace dammloam::soak
