#include "tools/bridge/client_registry.hpp"

#include <algorithm>

#include "tools/bridge/foxglove_protocol.hpp"

namespace dammloam::bridge {

std::string Client::AddSubscription(std::uint32_t id, std::uint32_t channel,
                                    const std::set<std::uint32_t>& known_channels) {
  if (known_channels.count(channel) == 0) {
    return "subscribe: unknown channel id " + std::to_string(channel);
  }
  std::lock_guard lock(mutex_);
  if (channel_of_.count(id) != 0) {
    return "subscribe: subscription id " + std::to_string(id) + " is already in use";
  }
  for (const auto& [other_id, other_channel] : channel_of_) {
    if (other_channel == channel) {
      return "subscribe: channel " + std::to_string(channel) + " is already subscribed as id " +
             std::to_string(other_id);
    }
  }
  channel_of_[id] = channel;
  return {};
}

std::string Client::RemoveSubscription(std::uint32_t id) {
  std::lock_guard lock(mutex_);
  if (channel_of_.erase(id) == 0) {
    return "unsubscribe: no subscription with id " + std::to_string(id);
  }
  return {};
}

std::vector<std::uint32_t> Client::SubscriptionsOn(std::uint32_t channel) const {
  std::lock_guard lock(mutex_);
  std::vector<std::uint32_t> ids;
  for (const auto& [id, c] : channel_of_) {
    if (c == channel) ids.push_back(id);
  }
  return ids;
}

void ClientRegistry::Add(const std::shared_ptr<Client>& client) {
  std::lock_guard lock(mutex_);
  clients_.push_back(client);
}

void ClientRegistry::Remove(const std::shared_ptr<Client>& client) {
  std::lock_guard lock(mutex_);
  const auto it = std::find(clients_.begin(), clients_.end(), client);
  if (it == clients_.end()) return;
  dropped_by_closed_ += client->queue.dropped();
  queued_by_closed_ += client->queue.pushed();
  clients_.erase(it);
}

void ClientRegistry::Publish(std::uint32_t channel, std::uint64_t timestamp_ns,
                             const std::shared_ptr<const std::string>& payload) {
  std::vector<std::shared_ptr<Client>> clients;
  {
    std::lock_guard lock(mutex_);
    clients = clients_;
  }
  for (const auto& client : clients) {
    bool pushed = false;
    for (std::uint32_t id : client->SubscriptionsOn(channel)) {
      Frame frame;
      frame.binary = true;
      frame.prefix = MessageDataPrefix(id, timestamp_ns);
      frame.prefix_size = frame.prefix.size();
      frame.payload = payload;
      client->queue.Push(std::move(frame));
      pushed = true;
    }
    if (pushed && client->wake) client->wake();
  }
}

bool ClientRegistry::HasSubscribers(std::uint32_t channel) const {
  std::lock_guard lock(mutex_);
  return std::any_of(clients_.begin(), clients_.end(), [channel](const auto& client) {
    return !client->SubscriptionsOn(channel).empty();
  });
}

std::size_t ClientRegistry::clients() const {
  std::lock_guard lock(mutex_);
  return clients_.size();
}

std::uint64_t ClientRegistry::frames_dropped() const {
  std::lock_guard lock(mutex_);
  std::uint64_t total = dropped_by_closed_;
  for (const auto& client : clients_) total += client->queue.dropped();
  return total;
}

std::uint64_t ClientRegistry::frames_queued() const {
  std::lock_guard lock(mutex_);
  std::uint64_t total = queued_by_closed_;
  for (const auto& client : clients_) total += client->queue.pushed();
  return total;
}

}  // namespace dammloam::bridge
