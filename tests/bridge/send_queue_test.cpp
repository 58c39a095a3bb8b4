// tools/bridge/send_queue: a slow client loses its oldest frames, counted, within both limits.
#include <gtest/gtest.h>

#include <thread>

#include "tools/bridge/foxglove_protocol.hpp"
#include "tools/bridge/send_queue.hpp"

namespace dammloam::bridge {
namespace {

Frame FrameOf(std::size_t bytes, char fill = 'x') {
  return TextFrame(std::string(bytes, fill));
}

TEST(SendQueue, KeepsTheNewestFramesAndCountsTheDropped) {
  SendQueue queue({/*max_frames=*/3, /*max_bytes=*/1 << 20});
  for (char c : std::string("abcde")) queue.Push(FrameOf(10, c));
  EXPECT_EQ(queue.frames(), 3u);
  EXPECT_EQ(queue.dropped(), 2u);
  EXPECT_EQ(queue.pushed(), 5u);
  for (char expected : std::string("cde")) {
    const auto frame = queue.Pop();
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->payload->front(), expected);
  }
  EXPECT_FALSE(queue.Pop());
  EXPECT_EQ(queue.bytes(), 0u);
}

TEST(SendQueue, ByteLimitDropsOldestFirst) {
  SendQueue queue({/*max_frames=*/100, /*max_bytes=*/100});
  queue.Push(FrameOf(40, 'a'));
  queue.Push(FrameOf(40, 'b'));
  queue.Push(FrameOf(40, 'c'));  // 120 > 100: 'a' goes
  EXPECT_EQ(queue.frames(), 2u);
  EXPECT_EQ(queue.bytes(), 80u);
  EXPECT_EQ(queue.dropped(), 1u);
  EXPECT_EQ(queue.Pop()->payload->front(), 'b');
}

TEST(SendQueue, AnOversizedFrameIsKeptAloneSoMemoryStaysBounded) {
  SendQueue queue({/*max_frames=*/10, /*max_bytes=*/100});
  queue.Push(FrameOf(30));
  queue.Push(FrameOf(30));
  queue.Push(FrameOf(500, 'z'));
  EXPECT_EQ(queue.frames(), 1u);
  EXPECT_EQ(queue.bytes(), 500u);
  EXPECT_EQ(queue.dropped(), 2u);
}

TEST(SendQueue, MessageDataPrefixCountsIntoTheBytes) {
  SendQueue queue;
  Frame frame = FrameOf(7);
  frame.prefix = MessageDataPrefix(1, 2);
  frame.prefix_size = frame.prefix.size();
  queue.Push(frame);
  EXPECT_EQ(queue.bytes(), 20u);
}

// A producer that never stops against a consumer that takes nothing: the queue stays within
// its limit and the producer finishes (it never waits). Also run under TSan with a consumer.
TEST(SendQueue, ProducerAndConsumerThreadsKeepEveryFrameAccountedFor) {
  SendQueue queue({/*max_frames=*/16, /*max_bytes=*/1 << 20});
  constexpr int kFrames = 20000;
  std::uint64_t popped = 0;
  std::thread consumer([&] {
    std::uint64_t seen = 0;
    while (seen + queue.dropped() < kFrames) {
      if (queue.Pop()) ++seen;
    }
    popped = seen;
  });
  for (int i = 0; i < kFrames; ++i) {
    queue.Push(FrameOf(8));
    EXPECT_LE(queue.frames(), 16u);
  }
  consumer.join();
  EXPECT_EQ(popped + queue.dropped() + queue.frames(), static_cast<std::uint64_t>(kFrames));
}

}  // namespace
}  // namespace dammloam::bridge
