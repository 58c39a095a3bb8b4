#pragma once
// One client's bounded send queue. The DDS thread pushes, the client's writer pops; when the
// client does not keep up, the oldest frames are dropped (and counted) so that a slow or stalled
// client costs a bounded amount of memory and never makes the producer wait.
#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace dammloam::bridge {

struct SendQueueLimits {
  std::size_t max_frames = 64;          // frames waiting per client
  std::size_t max_bytes = 16u << 20;    // payload bytes waiting per client
};

// One WebSocket message: a small per-client prefix (the messageData header: opcode,
// subscription id, timestamp) and a payload shared by every client that gets it.
struct Frame {
  bool binary = false;
  std::array<std::uint8_t, 13> prefix{};
  std::size_t prefix_size = 0;
  std::shared_ptr<const std::string> payload;

  std::size_t size() const { return prefix_size + (payload ? payload->size() : 0); }
};

class SendQueue {
 public:
  explicit SendQueue(const SendQueueLimits& limits = {}) : limits_(limits) {}

  // Appends the frame, first dropping the oldest frames while either limit would be exceeded.
  // A frame larger than max_bytes on its own is still queued (alone), so memory stays within
  // max_bytes plus the largest message. Never blocks on the consumer.
  void Push(Frame frame);
  // The oldest frame, or nothing when empty.
  std::optional<Frame> Pop();

  std::size_t frames() const;
  std::size_t bytes() const;
  std::uint64_t dropped() const;   // frames dropped for this client so far
  std::uint64_t pushed() const;

 private:
  const SendQueueLimits limits_;
  mutable std::mutex mutex_;
  std::deque<Frame> frames_;
  std::size_t bytes_ = 0;
  std::uint64_t dropped_ = 0;
  std::uint64_t pushed_ = 0;
};

}  // namespace dammloam::bridge
