#pragma once
// The bridge's DDS side: reads dammloamd's topics on its own thread and hands each channel's
// encoded message to the server. Readers use the daemon's QoS (reliable keep-last: a slow bridge
// loses old samples in its own reader, the daemon's writers never wait for it).
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "services/dds/topics.hpp"
#include "tools/bridge/bridge_messages.hpp"
#include "tools/bridge/ws_server.hpp"

namespace dammloam::bridge {

struct FeedConfig {
  std::uint32_t domain = 0;
  dds::TopicNames topics;
  std::size_t cloud_budget = 20'000;  // points per labelled cloud sent (0 = all)
  MapConfig map;
  double map_period_s = 1.0;          // map and trajectory re-sent this often
  double trajectory_spacing_m = 0.05; // trajectory vertex spacing
};

// Runs until `stop` is set (checked every 100 ms). Throws dds::DdsError when DDS cannot start.
void RunDdsFeed(const FeedConfig& config, WsServer& server, const std::atomic<bool>& stop);

}  // namespace dammloam::bridge
