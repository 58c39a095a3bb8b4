#include "tools/soak/map_saves.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/mapstore/map_store.hpp"

namespace dammloam::soak {
namespace {

// A large map takes a while to export and fsync on a loaded machine; the soak waits that long.
constexpr int kCommandTimeoutSeconds = 600;

std::string SaveName(std::size_t after_scans) {
  char name[32];
  std::snprintf(name, sizeof(name), "save-%06zu", after_scans);
  return name;
}

// dammloam-command prints the daemon's reply ("ok: ..." / "error: ...") as its last line.
std::string LastLine(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

}  // namespace

MapSaves::MapSaves(std::uint32_t domain, std::filesystem::path map_root,
                   std::filesystem::path log_dir)
    : domain_(domain), map_root_(std::move(map_root)), log_dir_(std::move(log_dir)) {}

void MapSaves::Request(std::size_t after_scans) {
  SaveRecord record;
  record.name = SaveName(after_scans);
  record.after_scans = after_scans;
  const std::filesystem::path log = log_dir_ / (record.name + ".log");
  // A relative directory: the daemon resolves it inside its map root.
  auto process = std::make_unique<tools::ChildProcess>(
      tools::SiblingExecutable("dammloam-command"),
      std::vector<std::string>{"save_map", record.name, "--domain", std::to_string(domain_),
                               "--timeout", std::to_string(kCommandTimeoutSeconds)},
      tools::ChildOutput{log, false});
  records_.push_back(record);
  running_.push_back({records_.size() - 1, std::move(process), std::chrono::steady_clock::now(),
                      log});
  spdlog::info("save_map {} requested after {} scans", record.name, after_scans);
}

void MapSaves::Reap() {
  for (Running& r : running_) {
    if (const auto status = r.process->ExitStatus()) Finish(r, *status);
  }
  std::erase_if(running_, [](const Running& r) { return r.process->ExitStatus().has_value(); });
}

void MapSaves::Finish(Running& running, int exit_code) {
  SaveRecord& record = records_[running.record];
  record.command_exit = exit_code;
  record.command_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - running.started).count();
  record.reply = LastLine(running.log);
  if (exit_code == 0) {
    spdlog::info("save_map {}: {} ({:.1f} s)", record.name, record.reply, record.command_seconds);
  } else {
    spdlog::error("save_map {}: dammloam-command exit {}: {}", record.name, exit_code,
                  record.reply);
  }
}

bool MapSaves::AllAnswered() const { return running_.empty(); }

void MapSaves::AddShutdownSave(const std::string& name) {
  SaveRecord record;
  record.name = name;
  record.reply = "save_map_on_shutdown";
  records_.push_back(record);
}

void MapSaves::LoadAll() {
  for (SaveRecord& record : records_) {
    if (record.after_scans != 0 && record.command_exit != 0) continue;  // nothing was saved
    try {
      const backend::MapData map = mapstore::LoadMap(map_root_ / record.name);
      record.loaded = !map.keyframes.empty();
      if (!record.loaded) record.load_error = "the map has no keyframe";
      record.keyframes = map.keyframes.size();
      record.loops = map.loops.size();
      record.map_points = map.global_points.size();
    } catch (const std::exception& e) {
      record.load_error = e.what();
    }
  }
}

}  // namespace dammloam::soak
