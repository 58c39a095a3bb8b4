// dammloam-bridge: dammloamd's DDS topics served live to Foxglove / Lichtblick over the Foxglove
// WebSocket protocol, and a page (three.js) at http://ADDR:PORT/ that draws the same channels.
// A process of its own, so that the daemon never waits on a viewer.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <thread>

#include "tools/bridge/dds_feed.hpp"
#include "tools/bridge/listen_address.hpp"
#include "tools/bridge/ws_server.hpp"
#include "tools/common/dds_tool_main.hpp"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void OnSignal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  using namespace dammloam;
  bridge::ServerConfig server_config;
  server_config.web_root = DAMMLOAM_BRIDGE_WEB_ROOT;
  bridge::FeedConfig feed;
  std::string listen = "127.0.0.1:8765";
  bool allow_default_network = false;
  double stats_period = 10.0;

  CLI::App app{"dammloam-bridge: dammloamd live over the Foxglove WebSocket protocol and a page"};
  app.add_option("--domain", feed.domain, "DDS domain id of dammloamd")
      ->check(CLI::Range(0u, 232u));
  app.add_option("--listen", listen,
                 "ADDR:PORT to serve on (default 127.0.0.1:8765, loopback only; port 0 = any)");
  app.add_option("--token", server_config.token,
                 "WebSocket clients must present it: ws://ADDR:PORT/?token=T or "
                 "'Authorization: Bearer T' (default: none)");
  app.add_option("--web-root", server_config.web_root, "folder with index.html and viewer.js");
  app.add_option("--cloud-budget", feed.cloud_budget,
                 "points per labelled cloud sent (every k-th point; 0 = all)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{10'000'000}));
  app.add_option("--map-voxel", feed.map.voxel_size, "map voxel size in metres")
      ->check(CLI::PositiveNumber);
  app.add_option("--map-max-points", feed.map.max_points, "map size limit (voxels)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{50'000'000}));
  app.add_option("--map-period", feed.map_period_s, "seconds between map and trajectory sends")
      ->check(CLI::PositiveNumber);
  app.add_option("--queue-frames", server_config.queue.max_frames,
                 "frames waiting per client before the oldest are dropped")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000}));
  std::size_t queue_mib = server_config.queue.max_bytes >> 20;
  app.add_option("--queue-mib", queue_mib,
                 "MiB waiting per client before the oldest frames are dropped")
      ->check(CLI::Range(std::size_t{1}, std::size_t{4096}));
  app.add_option("--max-clients", server_config.max_clients,
                 "WebSocket clients at once; more are refused (HTTP 503)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10'000}));
  app.add_option("--stats-period", stats_period, "seconds between log lines of counters")
      ->check(CLI::PositiveNumber);
  app.add_flag("--allow-default-network", allow_default_network,
               "allow DDS without CYCLONEDDS_URI (Cyclone's default interface)");
  CLI11_PARSE(app, argc, argv);
  server_config.queue.max_bytes = queue_mib << 20;

  return tools::RunDdsTool(allow_default_network, [&] {
    const bridge::ListenAddress address = bridge::ParseListenAddress(listen);
    server_config.address = address.host;
    server_config.port = address.port;
    bridge::WsServer server(server_config, bridge::BridgeChannels());
    const std::string where = address.host + ":" + std::to_string(server.port());
    // One line on stdout, flushed, for scripts (tools/demo.sh, the tests) to read the port.
    std::printf("dammloam-bridge: page http://%s/  Foxglove ws://%s/%s\n", where.c_str(),
                where.c_str(), server_config.token.empty() ? "" : "?token=...");
    std::fflush(stdout);
    std::signal(SIGINT, OnSignal);
    std::signal(SIGTERM, OnSignal);

    std::thread stats([&] {
      auto next = std::chrono::steady_clock::now();
      while (!g_stop) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        if (std::chrono::steady_clock::now() < next) continue;
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(stats_period));
        const bridge::ServerStats s = server.Stats();
        spdlog::info("bridge: {} clients, {} frames queued, {} dropped, {} requests refused",
                     s.clients, s.frames_queued, s.frames_dropped, s.rejected_requests);
      }
    });
    try {
      bridge::RunDdsFeed(feed, server, g_stop);
    } catch (...) {
      g_stop = true;
      stats.join();
      throw;
    }
    stats.join();
    return 0;
  });
}
