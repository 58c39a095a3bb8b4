// tools/bridge/client_registry: who gets which channel, with which subscription id.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <thread>

#include "tools/bridge/client_registry.hpp"

namespace dammloam::bridge {
namespace {

const std::set<std::uint32_t> kChannels = {1, 2, 3};

std::uint32_t SubscriptionIdOf(const Frame& frame) {
  std::uint32_t id = 0;
  std::memcpy(&id, frame.prefix.data() + 1, 4);
  return id;
}

TEST(ClientRegistry, OnlySubscribersGetAChannelWithTheirOwnSubscriptionId) {
  ClientRegistry registry;
  auto a = std::make_shared<Client>(SendQueueLimits{});
  auto b = std::make_shared<Client>(SendQueueLimits{});
  int wakes_a = 0;
  a->wake = [&] { ++wakes_a; };
  registry.Add(a);
  registry.Add(b);
  EXPECT_EQ(a->AddSubscription(7, 2, kChannels), "");
  EXPECT_EQ(b->AddSubscription(9, 3, kChannels), "");
  EXPECT_TRUE(registry.HasSubscribers(2));
  EXPECT_FALSE(registry.HasSubscribers(1));

  registry.Publish(2, 1234, std::make_shared<const std::string>("payload"));
  ASSERT_EQ(a->queue.frames(), 1u);
  EXPECT_EQ(b->queue.frames(), 0u);
  EXPECT_EQ(wakes_a, 1);
  const Frame frame = *a->queue.Pop();
  EXPECT_TRUE(frame.binary);
  EXPECT_EQ(frame.prefix[0], 0x01);
  EXPECT_EQ(SubscriptionIdOf(frame), 7u);
  std::uint64_t stamp = 0;
  std::memcpy(&stamp, frame.prefix.data() + 5, 8);
  EXPECT_EQ(stamp, 1234u);
  EXPECT_EQ(*frame.payload, "payload");
}

TEST(ClientRegistry, BadSubscriptionsAreRefusedWithAReason) {
  Client client{SendQueueLimits{}};
  EXPECT_NE(client.AddSubscription(1, 99, kChannels).find("unknown channel id 99"),
            std::string::npos);
  EXPECT_EQ(client.AddSubscription(1, 1, kChannels), "");
  EXPECT_NE(client.AddSubscription(1, 2, kChannels).find("already in use"), std::string::npos);
  EXPECT_NE(client.AddSubscription(2, 1, kChannels).find("already subscribed"), std::string::npos);
  EXPECT_NE(client.RemoveSubscription(5).find("no subscription with id 5"), std::string::npos);
  EXPECT_EQ(client.RemoveSubscription(1), "");
  EXPECT_TRUE(client.SubscriptionsOn(1).empty());
}

TEST(ClientRegistry, ClosedClientsKeepTheirDropCount) {
  ClientRegistry registry;
  auto client = std::make_shared<Client>(SendQueueLimits{/*max_frames=*/1, 1 << 20});
  registry.Add(client);
  ASSERT_EQ(client->AddSubscription(1, 1, kChannels), "");
  for (int i = 0; i < 5; ++i) registry.Publish(1, 0, std::make_shared<const std::string>("x"));
  EXPECT_EQ(registry.frames_dropped(), 4u);
  registry.Remove(client);
  EXPECT_EQ(registry.clients(), 0u);
  EXPECT_EQ(registry.frames_dropped(), 4u);
  EXPECT_EQ(registry.frames_queued(), 5u);
}

// The DDS thread publishes while the I/O thread subscribes, drains and removes clients (TSan).
TEST(ClientRegistry, PublishingWhileClientsComeAndGoIsSafe) {
  ClientRegistry registry;
  std::atomic<bool> stop{false};
  std::thread publisher([&] {
    const auto payload = std::make_shared<const std::string>("cdr");
    while (!stop) registry.Publish(1, 0, payload);
  });
  std::uint64_t received = 0;
  for (int round = 0; round < 200; ++round) {
    auto client = std::make_shared<Client>(SendQueueLimits{8, 1 << 20});
    registry.Add(client);
    ASSERT_EQ(client->AddSubscription(1, 1, kChannels), "");
    while (client->queue.frames() == 0) std::this_thread::yield();
    while (client->queue.Pop()) ++received;
    EXPECT_EQ(client->RemoveSubscription(1), "");
    registry.Remove(client);
  }
  stop = true;
  publisher.join();
  EXPECT_GE(received, 200u);
  EXPECT_EQ(registry.clients(), 0u);
}

}  // namespace
}  // namespace dammloam::bridge
