// dammloam-command: sends one Command to dammloamd (save_map DIR, relocalize DIR, ...) and waits
// for the CommandReply with the same request id.
// Exit codes: 0 the daemon did it; 1 the daemon answered with an error (or a local DDS failure,
// printed); 2 bad usage or no CYCLONEDDS_URI; 3 no reply within --timeout (no daemon found, or
// the daemon did not answer in time: the command may still run).
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>

#include "services/dds/dds.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "tools/common/dds_tool_main.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace dammloam;

constexpr int kExitOk = 0;
constexpr int kExitDaemonError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitTimeout = 3;

struct Options {
  std::string name;
  std::string argument;
  std::uint32_t domain = 0;
  double timeout = 30.0;  // a save_map of a large map or a relocalize takes seconds
  dds::TopicNames topics;
  std::string token;  // dammloamd.commands.token; --token or DAMMLOAM_COMMAND_TOKEN
  bool allow_default_network = false;
};

struct Reply {
  bool ok = false;
  std::string message;
};

// Unique among concurrent senders without coordination: microseconds since the epoch (modulo
// 2^42, ~51 days) in the high bits and the pid (Linux pid_max <= 2^22) in the low 22 bits.
// Unsigned overflow of the shift drops the clock's top bits, which is intended.
std::uint64_t FreshRequestId() {
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(
      std::chrono::system_clock::now().time_since_epoch()).count();
  return (static_cast<std::uint64_t>(us) << 22) |
         (static_cast<std::uint64_t>(::getpid()) & 0x3FFFFFu);
}

// Polls `ready` until it holds or the deadline passes (discovery has no waitable condition in
// our wrappers).
template <typename Pred>
bool WaitUntil(Pred&& ready, Clock::time_point deadline) {
  while (!ready()) {
    if (Clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

void Send(const dds::Writer<dammloam_msg_Command>& writer, std::uint64_t request_id,
          const Options& o) {
  dammloam_msg_Command msg{};
  msg.header.stamp = dds::ToMsgTime(std::chrono::duration<double>(
      std::chrono::system_clock::now().time_since_epoch()).count());
  msg.header.frame_id = const_cast<char*>("");
  msg.request_id = request_id;
  msg.name = const_cast<char*>(o.name.c_str());
  msg.argument = const_cast<char*>(o.argument.c_str());
  msg.token = const_cast<char*>(o.token.c_str());
  writer.Write(msg);
}

// Replies are latched, so earlier requests' replies arrive too: only ours counts.
std::optional<Reply> WaitForReply(const dds::Reader<dammloam_msg_CommandReply>& reader,
                                  const dds::WaitSet& waitset, std::uint64_t request_id,
                                  Clock::time_point deadline) {
  std::optional<Reply> reply;
  while (!reply && Clock::now() < deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    waitset.Wait(std::clamp(left, std::chrono::milliseconds(1), std::chrono::milliseconds(100)));
    reader.TakeEach([&](const dammloam_msg_CommandReply& m, const dds_sample_info_t&) {
      if (m.request_id != request_id) return;
      reply = Reply{m.ok, m.message != nullptr ? m.message : ""};
    });
  }
  return reply;
}

int PrintReply(const Reply& reply) {
  fmt::print("{}: {}\n", reply.ok ? "ok" : "error", reply.message);
  return reply.ok ? kExitOk : kExitDaemonError;
}

int Run(const Options& o) {
  // One deadline for the whole exchange, so the tool never outlives --timeout by much.
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(o.timeout));
  dds::Participant participant(static_cast<dds_domainid_t>(o.domain));
  dds::Topic command_topic(participant, dammloam_msg_Command_desc, o.topics.command,
                           dds::CommandQos());
  dds::Topic reply_topic(participant, dammloam_msg_CommandReply_desc, o.topics.command_reply,
                         dds::CommandReplyQos());
  dds::Writer<dammloam_msg_Command> writer(participant, command_topic, dds::CommandQos());
  dds::Reader<dammloam_msg_CommandReply> reader(participant, reply_topic, dds::CommandReplyQos());
  dds::WaitSet waitset(participant);
  waitset.Attach(reader);

  // Commands are volatile: a sample written before the daemon's reader matched is lost.
  if (!WaitUntil([&] { return writer.MatchedReaders() > 0 && reader.MatchedWriters() > 0; },
                 deadline)) {
    spdlog::error("no dammloamd on topics '{}'/'{}' (domain {}) within {} s: is it running with "
                  "the same CYCLONEDDS_URI and domain?", o.topics.command,
                  o.topics.command_reply, o.domain, o.timeout);
    return kExitTimeout;
  }
  const std::uint64_t request_id = FreshRequestId();
  Send(writer, request_id, o);
  spdlog::debug("sent request {}: {} '{}'", request_id, o.name, o.argument);
  if (const auto reply = WaitForReply(reader, waitset, request_id, deadline)) {
    return PrintReply(*reply);
  }
  spdlog::error("no reply to request {} ({} '{}') within {} s; the daemon may still carry it out",
                request_id, o.name, o.argument, o.timeout);
  return kExitTimeout;
}

void AddOptions(CLI::App& app, Options& o) {
  app.add_option("name", o.name, "command: save_map, relocalize (the daemon judges the name)")
      ->required();
  app.add_option("argument", o.argument, "the command's argument (a directory)");
  app.add_option("--domain", o.domain, "DDS domain id")->check(CLI::Range(0u, 232u));
  app.add_option("--timeout", o.timeout,
                 "seconds to wait for the daemon and its reply (exit 3 after that)")
      ->check(CLI::PositiveNumber);
  app.add_option("--command-topic", o.topics.command, "Command topic");
  app.add_option("--reply-topic", o.topics.command_reply, "CommandReply topic");
  app.add_option("--token", o.token,
                 "the daemon's dammloamd.commands.token (default: $DAMMLOAM_COMMAND_TOKEN, "
                 "which keeps it out of the process list)")
      ->envname("DAMMLOAM_COMMAND_TOKEN");
  app.add_flag("--allow-default-network", o.allow_default_network,
               "run without CYCLONEDDS_URI (uses the default network interface)");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"dammloam-command: send one command to dammloamd and print its reply"};
  app.footer("exit codes: 0 ok, 1 the daemon answered with an error (or a local failure, "
             "printed), 2 bad usage or no CYCLONEDDS_URI, 3 no reply within --timeout");
  AddOptions(app, o);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 would exit with its own codes (105, 106, ...): scripts get the documented 2.
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  return tools::RunDdsTool(o.allow_default_network, [&] { return Run(o); });
}
