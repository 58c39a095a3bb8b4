#pragma once
// The bridge's network side: one listening socket serving the page (HTTP GET) and the Foxglove
// WebSocket protocol (upgrade with subprotocol foxglove.websocket.v1) on one I/O thread.
// Boost.Beast stays inside ws_server.cpp.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tools/bridge/foxglove_protocol.hpp"
#include "tools/bridge/send_queue.hpp"

namespace dammloam::bridge {

struct ServerConfig {
  std::string address = "127.0.0.1";  // loopback unless configured otherwise
  std::uint16_t port = 8765;          // 0 = any free port (see WsServer::port)
  // When set, a WebSocket client must present it: query parameter ?token=..., or the header
  // "Authorization: Bearer ...". The page itself (static files) is served without it.
  std::string token;
  std::string web_root;               // folder with index.html and viewer.js
  SendQueueLimits queue;              // per client
  std::size_t max_client_message = 64 * 1024;  // bytes; a larger frame closes that client
  // WebSocket clients at once (each may hold a full queue): more are refused with HTTP 503.
  std::size_t max_clients = 32;
};

struct ServerStats {
  std::size_t clients = 0;
  std::uint64_t frames_dropped = 0;  // all clients, closed ones included
  std::uint64_t frames_queued = 0;
  std::uint64_t rejected_requests = 0;  // malformed client messages, refused handshakes
};

class WsServer {
 public:
  // Binds and listens; throws std::runtime_error naming the address when that fails.
  WsServer(const ServerConfig& config, std::vector<Channel> channels);
  ~WsServer();
  WsServer(const WsServer&) = delete;
  WsServer& operator=(const WsServer&) = delete;

  std::uint16_t port() const;
  // Thread-safe. Queues the payload for every client subscribed to the channel; never waits.
  void Publish(std::uint32_t channel_id, std::uint64_t timestamp_ns,
               std::shared_ptr<const std::string> payload);
  // Thread-safe. Whether any client is subscribed to the channel (skip the encoding if not).
  bool HasSubscribers(std::uint32_t channel_id) const;
  ServerStats Stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dammloam::bridge
