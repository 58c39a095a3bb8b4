#include "services/dammloamd/command_stage.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <vector>

#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::daemon {
namespace {

std::string KnownNames(const std::map<std::string, CommandHandler>& handlers) {
  std::string names;
  for (const auto& [name, handler] : handlers) names += (names.empty() ? "" : ", ") + name;
  return names;
}

}  // namespace

CommandStage::CommandStage(const dds::Participant& participant, const DaemonConfig& config,
                           std::map<std::string, CommandHandler> handlers, CommandEvents events)
    : map_frame_(config.map_frame),
      gate_(config.commands),
      handlers_(std::move(handlers)),
      events_(std::move(events)),
      command_topic_(participant, dammloam_msg_Command_desc, config.topics.command,
                     dds::CommandQos()),
      reply_topic_(participant, dammloam_msg_CommandReply_desc, config.topics.command_reply,
                   dds::CommandReplyQos()),
      reader_(participant, command_topic_, dds::CommandQos()),
      writer_(participant, reply_topic_, dds::CommandReplyQos()),
      waitset_(participant) {
  waitset_.Attach(reader_);
}

void CommandStage::Start() { thread_ = std::thread([this] { Loop(); }); }

void CommandStage::Stop() {
  stop_ = true;
  waitset_.Wake();
  if (thread_.joinable()) thread_.join();
}

void CommandStage::Loop() {
  while (!stop_) {
    try {
      waitset_.Wait(std::chrono::milliseconds(100));
      // Copy the commands out first: a handler may take seconds and must not hold DDS loans.
      // The sender is looked up now, while its writer is surely still matched.
      std::vector<CommandRequest> requests;
      reader_.TakeEach([&](const dammloam_msg_Command& c, const dds_sample_info_t& info) {
        requests.push_back({c.request_id, c.name != nullptr ? c.name : "",
                            c.argument != nullptr ? c.argument : "",
                            {dds::SenderParticipantGuid(reader_, info.publication_handle),
                             c.token != nullptr ? c.token : ""}});
      });
      for (const CommandRequest& request : requests) Execute(request);
    } catch (const std::exception& e) {
      spdlog::error("command stage: {}", e.what());
    }
  }
}

void CommandStage::Execute(const CommandRequest& request) {
  spdlog::info("command {} '{}' '{}' from participant {}", request.request_id, request.name,
               request.argument, request.credentials.sender_guid);
  if (const auto refusal = gate_.Admit(request.credentials)) return Refuse(request, *refusal);
  const auto handler = handlers_.find(request.name);
  if (handler == handlers_.end()) {
    return Finish(request, {false, "unknown command '" + request.name + "' (known: " +
                                       KnownNames(handlers_) + ")"});
  }
  const ResolvedDirectory directory = gate_.Resolve(request.argument);
  if (directory.refusal) return Refuse(request, *directory.refusal);
  Finish(request, Run(handler->second, directory.path.string()));
}

void CommandStage::Finish(const CommandRequest& request, const CommandOutcome& outcome) {
  if (outcome.ok) {
    spdlog::info("command {} {}: {}", request.request_id, request.name, outcome.message);
  } else {
    spdlog::error("command {} {} failed: {}", request.request_id, request.name, outcome.message);
    events_.failed("command " + std::to_string(request.request_id) + " '" + request.name +
                   "' failed: " + outcome.message);
  }
  Reply(request, outcome);
}

void CommandStage::Refuse(const CommandRequest& request, const Refusal& refusal) {
  const std::string message = "refused [" + refusal.reason + "]: " + refusal.message;
  spdlog::warn("command {} '{}' from participant {} {}", request.request_id, request.name,
               request.credentials.sender_guid, message);
  events_.refused(refusal.reason, "command " + std::to_string(request.request_id) + " '" +
                                      request.name + "' " + message);
  Reply(request, {false, message});
}

CommandOutcome CommandStage::Run(const CommandHandler& handler,
                                 const std::string& directory) const {
  try {
    return handler(directory);
  } catch (const std::exception& e) {  // a handler bug must not end the command thread
    return {false, e.what()};
  }
}
void CommandStage::Reply(const CommandRequest& request, const CommandOutcome& outcome) {
  dammloam_msg_CommandReply msg{};
  msg.header.stamp = dds::ToMsgTime(std::chrono::duration<double>(
      std::chrono::system_clock::now().time_since_epoch()).count());
  msg.header.frame_id = const_cast<char*>(map_frame_.c_str());
  msg.header.seq = reply_seq_++;
  msg.request_id = request.request_id;
  msg.name = const_cast<char*>(request.name.c_str());
  msg.ok = outcome.ok;
  msg.message = const_cast<char*>(outcome.message.c_str());
  writer_.Write(msg);
}

}  // namespace dammloam::daemon
