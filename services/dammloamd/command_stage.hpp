#pragma once
// dammloamd's command thread: takes Command samples, lets CommandGate admit them (enabled,
// sender, token, directory inside the map root), runs the handler registered for the command's
// name and answers every request with a CommandReply. Handlers run here, one at a time, so a
// slow one (loading a map, waiting for a save) never touches the odometry stages.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <thread>

#include "services/dammloamd/command_gate.hpp"
#include "services/dammloamd/daemon_config.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/middleware_watch.hpp"

namespace dammloam::daemon {

struct CommandOutcome {
  bool ok = false;
  std::string message;
};

// Receives the command's directory, already resolved inside the map root (every command takes
// one); must not throw (CommandStage turns exceptions into errors).
using CommandHandler = std::function<CommandOutcome(const std::string& directory)>;

// One received command, copied out of the DDS loan.
struct CommandRequest {
  std::uint64_t request_id = 0;
  std::string name;
  std::string argument;
  CommandCredentials credentials;
};

// How the stage tells the daemon about failures (both called on the command thread).
struct CommandEvents {
  std::function<void(const std::string& message)> failed;  // admitted, then failed
  std::function<void(const std::string& reason, const std::string& message)> refused;
};

class CommandStage {
 public:
  CommandStage(const dds::Participant& participant, const DaemonConfig& config,
               std::map<std::string, CommandHandler> handlers, CommandEvents events);
  ~CommandStage() { Stop(); }
  CommandStage(const CommandStage&) = delete;
  CommandStage& operator=(const CommandStage&) = delete;

  void Start();
  // Lets `watch` report what DDS drops on the Command reader and the CommandReply writer.
  void WatchEndpoints(dds::MiddlewareWatch& watch) const {
    watch.Watch(reader_);
    watch.Watch(writer_);
  }
  // Waits for the command in work (if any) to finish and be answered.
  void Stop();

 private:
  void Loop();
  void Execute(const CommandRequest& request);
  void Finish(const CommandRequest& request, const CommandOutcome& outcome);
  void Refuse(const CommandRequest& request, const Refusal& refusal);
  CommandOutcome Run(const CommandHandler& handler, const std::string& directory) const;
  void Reply(const CommandRequest& request, const CommandOutcome& outcome);

  std::string map_frame_;
  CommandGate gate_;
  std::map<std::string, CommandHandler> handlers_;
  CommandEvents events_;
  dds::Topic command_topic_, reply_topic_;
  dds::Reader<dammloam_msg_Command> reader_;
  dds::Writer<dammloam_msg_CommandReply> writer_;
  dds::WaitSet waitset_;
  std::uint64_t reply_seq_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace dammloam::daemon
