#pragma once
// The server side of the Foxglove WebSocket protocol v1 (subprotocol foxglove.websocket.v1):
// the JSON the server sends (serverInfo, advertise, status), the binary messageData header, and
// the client's subscribe/unsubscribe requests, with every malformed request turned into an error
// text naming what is wrong. No sockets here: ws_server.cpp moves the bytes.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "tools/bridge/send_queue.hpp"

namespace dammloam::bridge {

inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";

struct Channel {
  std::uint32_t id = 0;
  std::string topic;
  std::string encoding;         // "cdr" or "json"
  std::string schema_name;      // e.g. nav_msgs/msg/Odometry
  std::string schema;           // ros2msg text or JSON Schema
  std::string schema_encoding;  // "ros2msg" or "jsonschema"
};

std::string ServerInfoJson(const std::string& name, const std::string& session_id);
std::string AdvertiseJson(const std::vector<Channel>& channels);
enum class StatusLevel { kInfo = 0, kWarning = 1, kError = 2 };
std::string StatusJson(StatusLevel level, const std::string& message);

// messageData (opcode 1): uint32 subscription id, uint64 receive timestamp (ns), little-endian.
std::array<std::uint8_t, 13> MessageDataPrefix(std::uint32_t subscription_id,
                                               std::uint64_t timestamp_ns);
Frame TextFrame(std::string json);

struct Subscribe {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> subscriptions;  // (id, channel id)
};
struct Unsubscribe {
  std::vector<std::uint32_t> subscription_ids;
};
// A request the bridge does not serve (a capability it does not advertise); answered with a
// status warning.
struct Unsupported {
  std::string op;
};
struct Malformed {
  std::string error;
};
using ClientRequest = std::variant<Subscribe, Unsubscribe, Unsupported, Malformed>;

// Parses one text frame from a client.
ClientRequest ParseClientText(const std::string& text);

}  // namespace dammloam::bridge
