#pragma once
// dammloamd's command thread: takes Command samples, runs the handler registered for the
// command's name and answers every request with a CommandReply. Handlers run here, one at a
// time, so a slow one (loading a map, waiting for a save) never touches the odometry stages.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <thread>

#include "services/dammloamd/daemon_config.hpp"
#include "services/dds/dds.hpp"

namespace dammloam::daemon {

struct CommandOutcome {
  bool ok = false;
  std::string message;
};

// Receives the command's argument; must not throw (CommandStage turns exceptions into errors).
using CommandHandler = std::function<CommandOutcome(const std::string& argument)>;

// One received command, copied out of the DDS loan.
struct CommandRequest {
  std::uint64_t request_id = 0;
  std::string name;
  std::string argument;
};

class CommandStage {
 public:
  // on_error is called (on the command thread) with the text of every failed command.
  CommandStage(const dds::Participant& participant, const DaemonConfig& config,
               std::map<std::string, CommandHandler> handlers,
               std::function<void(const std::string&)> on_error);
  ~CommandStage() { Stop(); }
  CommandStage(const CommandStage&) = delete;
  CommandStage& operator=(const CommandStage&) = delete;

  void Start();
  // Waits for the command in work (if any) to finish and be answered.
  void Stop();

 private:
  void Loop();
  void Execute(const CommandRequest& request);
  CommandOutcome Run(const CommandRequest& request) const;
  void Reply(const CommandRequest& request, const CommandOutcome& outcome);

  std::string map_frame_;
  std::map<std::string, CommandHandler> handlers_;
  std::function<void(const std::string&)> on_error_;
  dds::Topic command_topic_, reply_topic_;
  dds::Reader<dammloam_msg_Command> reader_;
  dds::Writer<dammloam_msg_CommandReply> writer_;
  dds::WaitSet waitset_;
  std::uint64_t reply_seq_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace dammloam::daemon
