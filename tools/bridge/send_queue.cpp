#include "tools/bridge/send_queue.hpp"

namespace dammloam::bridge {

void SendQueue::Push(Frame frame) {
  std::lock_guard lock(mutex_);
  const std::size_t size = frame.size();
  while (!frames_.empty() &&
         (frames_.size() + 1 > limits_.max_frames || bytes_ + size > limits_.max_bytes)) {
    bytes_ -= frames_.front().size();
    frames_.pop_front();
    ++dropped_;
  }
  bytes_ += size;
  frames_.push_back(std::move(frame));
  ++pushed_;
}

std::optional<Frame> SendQueue::Pop() {
  std::lock_guard lock(mutex_);
  if (frames_.empty()) return std::nullopt;
  Frame frame = std::move(frames_.front());
  frames_.pop_front();
  bytes_ -= frame.size();
  return frame;
}

std::size_t SendQueue::frames() const {
  std::lock_guard lock(mutex_);
  return frames_.size();
}

std::size_t SendQueue::bytes() const {
  std::lock_guard lock(mutex_);
  return bytes_;
}

std::uint64_t SendQueue::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

std::uint64_t SendQueue::pushed() const {
  std::lock_guard lock(mutex_);
  return pushed_;
}

}  // namespace dammloam::bridge
