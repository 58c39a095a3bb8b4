// The daemon's SPSC stage queue and its drop-oldest policy across two threads (run under TSan).
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "services/dammloamd/stage_queue.hpp"

namespace dammloam::daemon {
namespace {

TEST(StageQueue, DeliversEverythingInOrderWhenTheConsumerKeepsUp) {
  constexpr int kItems = 20000;
  StageQueue<std::vector<int>> queue(64, 1u << 30);  // never drop
  std::atomic<int> push_failures{0};
  std::thread producer([&] {
    for (int i = 0; i < kItems; ++i) {
      std::vector<int> item{i, i * 2};
      while (!queue.TryPush(std::move(item))) {
        push_failures.fetch_add(1);
        item = {i, i * 2};
        std::this_thread::yield();
      }
    }
  });
  std::vector<int> received;
  int dropped = 0;
  while (static_cast<int>(received.size()) < kItems) {
    auto item = queue.Pop(std::chrono::milliseconds(100), [&](std::vector<int>&&) { ++dropped; });
    if (item) {
      ASSERT_EQ(item->size(), 2u);
      EXPECT_EQ((*item)[1], 2 * (*item)[0]);
      received.push_back((*item)[0]);
    }
  }
  producer.join();
  EXPECT_EQ(dropped, 0);
  for (int i = 0; i < kItems; ++i) ASSERT_EQ(received[static_cast<std::size_t>(i)], i);
}

TEST(StageQueue, SlowConsumerDropsTheOldestAndCountsEveryItem) {
  constexpr int kItems = 400;
  StageQueue<int> queue(16, 1);
  std::atomic<bool> done{false};
  int push_failures = 0;
  int last_pushed = -1;
  std::thread producer([&] {
    for (int i = 0; i < kItems; ++i) {
      if (queue.TryPush(int{i})) {
        last_pushed = i;
      } else {
        ++push_failures;
      }
      if (i % 4 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    done = true;
  });
  std::vector<int> processed, dropped;
  while (!done || queue.SizeApprox() > 0) {
    auto item = queue.Pop(std::chrono::milliseconds(10), [&](int&& old) { dropped.push_back(old); });
    if (!item) continue;
    processed.push_back(*item);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));  // slower than the producer
  }
  producer.join();
  EXPECT_GT(dropped.size(), 0u);
  EXPECT_EQ(processed.size() + dropped.size() + static_cast<std::size_t>(push_failures),
            static_cast<std::size_t>(kItems));
  // Processed items are increasing: only older items were dropped.
  for (std::size_t i = 1; i < processed.size(); ++i) EXPECT_LT(processed[i - 1], processed[i]);
  EXPECT_EQ(processed.back(), last_pushed) << "the newest item must survive";
}

}  // namespace
}  // namespace dammloam::daemon
