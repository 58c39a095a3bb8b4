#pragma once
// Bounded lock-free single-producer/single-consumer queue between two daemon stages, with the
// daemon's overload policy: the consumer drops the OLDEST waiting items when too many pile up,
// so a slow stage always works on recent data and every drop is counted by the caller.
#include <readerwriterqueue/readerwriterqueue.h>

#include <chrono>
#include <cstddef>
#include <optional>

namespace dammloam::daemon {

template <typename T>
class StageQueue {
 public:
  // capacity: hard bound (the producer fails beyond it); max_backlog: how many items may wait
  // behind the one handed out; beyond that the consumer drops the oldest.
  StageQueue(std::size_t capacity, std::size_t max_backlog)
      : queue_(capacity), max_backlog_(max_backlog) {}

  // Producer side. False when the queue is full (the item is not enqueued).
  bool TryPush(T&& item) { return queue_.try_enqueue(std::move(item)); }

  // Consumer side. Waits up to `timeout` for an item; returns the oldest item that is allowed to
  // run and calls on_drop(T&&) for every older item skipped because of the backlog limit.
  template <typename OnDrop>
  std::optional<T> Pop(std::chrono::microseconds timeout, OnDrop&& on_drop) {
    T item{};
    if (!queue_.wait_dequeue_timed(item, timeout)) return std::nullopt;
    T next{};
    while (queue_.size_approx() > max_backlog_ && queue_.try_dequeue(next)) {
      on_drop(std::move(item));
      item = std::move(next);
    }
    return item;
  }

  std::size_t SizeApprox() const { return queue_.size_approx(); }

 private:
  moodycamel::BlockingReaderWriterQueue<T> queue_;
  std::size_t max_backlog_;
};

}  // namespace dammloam::daemon
