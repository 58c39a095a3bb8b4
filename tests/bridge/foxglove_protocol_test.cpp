// tools/bridge/foxglove_protocol: the server's JSON and the parsing of client frames, malformed
// ones included (each answered with an error naming the problem, never a crash).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tools/bridge/foxglove_protocol.hpp"

namespace dammloam::bridge {
namespace {

using nlohmann::json;

std::string ErrorOf(const std::string& text) {
  const ClientRequest request = ParseClientText(text);
  const auto* malformed = std::get_if<Malformed>(&request);
  return malformed != nullptr ? malformed->error : "(accepted)";
}

TEST(FoxgloveProtocol, ServerInfoAndAdvertiseFollowTheSpec) {
  const json info = json::parse(ServerInfoJson("dammloam-bridge", "s1"));
  EXPECT_EQ(info["op"], "serverInfo");
  EXPECT_EQ(info["name"], "dammloam-bridge");
  EXPECT_TRUE(info["capabilities"].is_array());
  EXPECT_EQ(info["sessionId"], "s1");

  const json advertise = json::parse(AdvertiseJson(
      {{3, "/odom", "cdr", "nav_msgs/msg/Odometry", "std_msgs/Header header\n", "ros2msg"}}));
  EXPECT_EQ(advertise["op"], "advertise");
  ASSERT_EQ(advertise["channels"].size(), 1u);
  const json& channel = advertise["channels"][0];
  EXPECT_EQ(channel["id"], 3);
  EXPECT_EQ(channel["topic"], "/odom");
  EXPECT_EQ(channel["encoding"], "cdr");
  EXPECT_EQ(channel["schemaName"], "nav_msgs/msg/Odometry");
  EXPECT_EQ(channel["schema"], "std_msgs/Header header\n");
  EXPECT_EQ(channel["schemaEncoding"], "ros2msg");
}

TEST(FoxgloveProtocol, MessageDataPrefixIsOpcodeIdAndStampLittleEndian) {
  const auto prefix = MessageDataPrefix(0x01020304u, 0x1122334455667788ull);
  const std::array<std::uint8_t, 13> expected = {0x01, 0x04, 0x03, 0x02, 0x01, 0x88, 0x77,
                                                 0x66, 0x55, 0x44, 0x33, 0x22, 0x11};
  EXPECT_EQ(prefix, expected);
}

TEST(FoxgloveProtocol, SubscribeAndUnsubscribeAreParsed) {
  const ClientRequest subscribe =
      ParseClientText(R"({"op":"subscribe","subscriptions":[{"id":3,"channelId":1},{"id":4,"channelId":6}]})");
  const auto* s = std::get_if<Subscribe>(&subscribe);
  ASSERT_NE(s, nullptr);
  ASSERT_EQ(s->subscriptions.size(), 2u);
  EXPECT_EQ(s->subscriptions[1], std::make_pair(4u, 6u));
  const ClientRequest unsubscribe = ParseClientText(R"({"op":"unsubscribe","subscriptionIds":[3]})");
  const auto* u = std::get_if<Unsubscribe>(&unsubscribe);
  ASSERT_NE(u, nullptr);
  EXPECT_EQ(u->subscription_ids, std::vector<std::uint32_t>{3});
  EXPECT_TRUE(std::holds_alternative<Unsupported>(
      ParseClientText(R"({"op":"getParameters","parameterNames":[]})")));
}

TEST(FoxgloveProtocol, MalformedClientTextNamesTheProblem) {
  EXPECT_EQ(ErrorOf("{not json"), "client message is not valid JSON");
  EXPECT_EQ(ErrorOf("[1,2]"), "client message must be a JSON object");
  EXPECT_EQ(ErrorOf(R"({"op":7})"), "client message needs a string 'op'");
  EXPECT_EQ(ErrorOf(R"({"op":"explode"})"), "unknown op 'explode'");
  EXPECT_EQ(ErrorOf(R"({"op":"subscribe"})"), "subscribe: 'subscriptions' must be an array");
  EXPECT_EQ(ErrorOf(R"({"op":"subscribe","subscriptions":[{"id":1}]})"),
            "subscribe: each subscription needs 'id' and 'channelId'");
  EXPECT_NE(ErrorOf(R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})")
                .find("unsigned 32-bit"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1}]})")
                .find("unsigned 32-bit"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1}]})")
                .find("unsigned 32-bit"),
            std::string::npos);
  EXPECT_EQ(ErrorOf(R"({"op":"unsubscribe","subscriptionIds":"3"})"),
            "unsubscribe: 'subscriptionIds' must be an array");
  EXPECT_EQ(ErrorOf(std::string("{\"op\":\"\xff\xfe\"}")), "client message is not valid JSON");
}

TEST(FoxgloveProtocol, StatusEchoingInvalidUtf8StaysValidJson) {
  const json status = json::parse(StatusJson(StatusLevel::kError, "bad \xff op"));
  EXPECT_EQ(status["op"], "status");
  EXPECT_EQ(status["level"], 2);
}

}  // namespace
}  // namespace dammloam::bridge
