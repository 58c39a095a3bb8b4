#include "tools/bridge/foxglove_protocol.hpp"

#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>

namespace dammloam::bridge {
namespace {

using nlohmann::json;

// The ops a client may send under the spec; those other than subscribe/unsubscribe need a
// capability this server does not advertise.
bool IsKnownClientOp(const std::string& op) {
  for (const char* known : {"clientAdvertise", "clientUnadvertise", "getParameters",
                            "setParameters", "subscribeParameterUpdates",
                            "unsubscribeParameterUpdates", "subscribeConnectionGraph",
                            "unsubscribeConnectionGraph", "fetchAsset"}) {
    if (op == known) return true;
  }
  return false;
}

// A JSON number that is an integer in uint32 range, or an error naming `what`.
std::variant<std::uint32_t, std::string> Uint32Of(const json& value, const std::string& what) {
  if (!value.is_number_integer() || value.is_number_float()) {
    return what + " must be an unsigned 32-bit integer";
  }
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (v <= std::numeric_limits<std::uint32_t>::max()) return static_cast<std::uint32_t>(v);
  }
  return what + " must be an unsigned 32-bit integer, got " + value.dump();
}

ClientRequest ParseSubscribe(const json& message) {
  const auto it = message.find("subscriptions");
  if (it == message.end() || !it->is_array()) {
    return Malformed{"subscribe: 'subscriptions' must be an array"};
  }
  Subscribe request;
  for (const json& entry : *it) {
    if (!entry.is_object() || !entry.contains("id") || !entry.contains("channelId")) {
      return Malformed{"subscribe: each subscription needs 'id' and 'channelId'"};
    }
    const auto id = Uint32Of(entry["id"], "subscribe: 'id'");
    if (const auto* e = std::get_if<std::string>(&id)) return Malformed{*e};
    const auto channel = Uint32Of(entry["channelId"], "subscribe: 'channelId'");
    if (const auto* e = std::get_if<std::string>(&channel)) return Malformed{*e};
    request.subscriptions.emplace_back(std::get<std::uint32_t>(id),
                                       std::get<std::uint32_t>(channel));
  }
  return request;
}

ClientRequest ParseUnsubscribe(const json& message) {
  const auto it = message.find("subscriptionIds");
  if (it == message.end() || !it->is_array()) {
    return Malformed{"unsubscribe: 'subscriptionIds' must be an array"};
  }
  Unsubscribe request;
  for (const json& entry : *it) {
    const auto id = Uint32Of(entry, "unsubscribe: each subscription id");
    if (const auto* e = std::get_if<std::string>(&id)) return Malformed{*e};
    request.subscription_ids.push_back(std::get<std::uint32_t>(id));
  }
  return request;
}

}  // namespace

std::string ServerInfoJson(const std::string& name, const std::string& session_id) {
  return json{{"op", "serverInfo"},
              {"name", name},
              {"capabilities", json::array()},
              {"supportedEncodings", json::array()},
              {"metadata", json::object()},
              {"sessionId", session_id}}
      .dump();
}

std::string AdvertiseJson(const std::vector<Channel>& channels) {
  json list = json::array();
  for (const Channel& c : channels) {
    list.push_back({{"id", c.id},
                    {"topic", c.topic},
                    {"encoding", c.encoding},
                    {"schemaName", c.schema_name},
                    {"schema", c.schema},
                    {"schemaEncoding", c.schema_encoding}});
  }
  return json{{"op", "advertise"}, {"channels", list}}.dump();
}

std::string StatusJson(StatusLevel level, const std::string& message) {
  // Replace, not throw, on invalid UTF-8 echoed from a client.
  return json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump(
      -1, ' ', false, json::error_handler_t::replace);
}

std::array<std::uint8_t, 13> MessageDataPrefix(std::uint32_t subscription_id,
                                               std::uint64_t timestamp_ns) {
  std::array<std::uint8_t, 13> prefix{};
  prefix[0] = 0x01;
  for (int i = 0; i < 4; ++i) prefix[1 + i] = static_cast<std::uint8_t>(subscription_id >> (8 * i));
  for (int i = 0; i < 8; ++i) prefix[5 + i] = static_cast<std::uint8_t>(timestamp_ns >> (8 * i));
  return prefix;
}

Frame TextFrame(std::string text) {
  Frame frame;
  frame.binary = false;
  frame.payload = std::make_shared<const std::string>(std::move(text));
  return frame;
}

ClientRequest ParseClientText(const std::string& text) {
  const json message = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (message.is_discarded()) return Malformed{"client message is not valid JSON"};
  if (!message.is_object()) return Malformed{"client message must be a JSON object"};
  const auto op = message.find("op");
  if (op == message.end() || !op->is_string()) {
    return Malformed{"client message needs a string 'op'"};
  }
  const std::string name = op->get<std::string>();
  if (name == "subscribe") return ParseSubscribe(message);
  if (name == "unsubscribe") return ParseUnsubscribe(message);
  if (IsKnownClientOp(name)) return Unsupported{name};
  return Malformed{"unknown op '" + name + "'"};
}

}  // namespace dammloam::bridge
