#pragma once
// Test-side commander of dammloamd: sends Command samples and collects CommandReply samples
// (copied out of the loans), waiting for the reply to a given request id.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "services/dds/dds.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::test {

struct ReceivedReply {
  std::uint64_t request_id = 0;
  std::string name;
  bool ok = false;
  std::string message;
};

class CommandClient {
 public:
  explicit CommandClient(std::uint32_t domain, const dds::TopicNames& topics = {})
      : participant_(static_cast<dds_domainid_t>(domain)),
        command_topic_(participant_, dammloam_msg_Command_desc, topics.command, dds::CommandQos()),
        reply_topic_(participant_, dammloam_msg_CommandReply_desc, topics.command_reply,
                     dds::CommandReplyQos()),
        commands_(participant_, command_topic_, dds::CommandQos()),
        replies_(participant_, reply_topic_, {true, 100, true}) {}

  // Commands are volatile: send only once the daemon's command reader matched.
  bool WaitForDaemon(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (commands_.MatchedReaders() > 0 && replies_.MatchedWriters() > 0) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  void Send(std::uint64_t request_id, const std::string& name, const std::string& argument,
            const std::string& token = "") {
    dammloam_msg_Command msg{};
    msg.header.frame_id = const_cast<char*>("");
    msg.request_id = request_id;
    msg.name = const_cast<char*>(name.c_str());
    msg.argument = const_cast<char*>(argument.c_str());
    msg.token = const_cast<char*>(token.c_str());
    commands_.Write(msg);
  }

  // Sends and waits for the reply with this request id.
  std::optional<ReceivedReply> Call(std::uint64_t request_id, const std::string& name,
                                    const std::string& argument,
                                    std::chrono::milliseconds timeout,
                                    const std::string& token = "") {
    Send(request_id, name, argument, token);
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      Poll();
      for (const ReceivedReply& r : replies) {
        if (r.request_id == request_id) return r;
      }
      if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

  void Poll() {
    replies_.TakeEach([this](const dammloam_msg_CommandReply& m, const dds_sample_info_t&) {
      replies.push_back({m.request_id, m.name != nullptr ? m.name : "", m.ok,
                         m.message != nullptr ? m.message : ""});
    }, 16);
  }

  // What the daemon sees as this commander's identity (dammloamd.commands.allowed_participants).
  std::string Guid() const { return dds::ParticipantGuid(participant_); }

  std::vector<ReceivedReply> replies;

 private:
  dds::Participant participant_;
  dds::Topic command_topic_, reply_topic_;
  dds::Writer<dammloam_msg_Command> commands_;
  dds::Reader<dammloam_msg_CommandReply> replies_;
};

}  // namespace dammloam::test
