#pragma once
// The clients the bridge serves and what each subscribed to, shared by the I/O thread (which
// adds, removes and subscribes clients) and the DDS thread (which publishes). No sockets here:
// a client is its send queue, its subscriptions and a function that wakes its writer.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "tools/bridge/send_queue.hpp"

namespace dammloam::bridge {

struct Client {
  explicit Client(const SendQueueLimits& limits) : queue(limits) {}
  SendQueue queue;
  std::atomic<bool> writing{false};  // the writer is busy or a wake-up is pending
  std::function<void()> wake;        // thread-safe: asks the writer to drain the queue

  // Subscribes (id -> channel); returns an error text, empty on success.
  std::string AddSubscription(std::uint32_t id, std::uint32_t channel,
                              const std::set<std::uint32_t>& known_channels);
  // Returns an error text for an id that was not subscribed, empty on success.
  std::string RemoveSubscription(std::uint32_t id);
  // The subscription ids on a channel (at most one under the spec).
  std::vector<std::uint32_t> SubscriptionsOn(std::uint32_t channel) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::uint32_t, std::uint32_t> channel_of_;  // subscription id -> channel
};

class ClientRegistry {
 public:
  void Add(const std::shared_ptr<Client>& client);
  void Remove(const std::shared_ptr<Client>& client);
  // Pushes the payload to every client subscribed to the channel, prefixed with that client's
  // subscription id, and wakes their writers. Never waits on a client.
  void Publish(std::uint32_t channel, std::uint64_t timestamp_ns,
               const std::shared_ptr<const std::string>& payload);
  bool HasSubscribers(std::uint32_t channel) const;
  std::size_t clients() const;
  std::uint64_t frames_dropped() const;  // closed clients included
  std::uint64_t frames_queued() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<Client>> clients_;
  std::uint64_t dropped_by_closed_ = 0;
  std::uint64_t queued_by_closed_ = 0;
};

}  // namespace dammloam::bridge
