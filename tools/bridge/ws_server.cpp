#include "tools/bridge/ws_server.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "tools/bridge/client_registry.hpp"

namespace dammloam::bridge {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

}  // namespace

// What every session needs from the server (named: WsServer::Impl holds it).
struct ServerShared {
  ServerConfig config;
  std::vector<Channel> channels;
  std::set<std::uint32_t> channel_ids;
  std::string advertise_json;
  ClientRegistry registry;
  std::atomic<std::uint64_t> rejected{0};
  std::atomic<std::uint64_t> next_session{1};
};

namespace {

using Shared = ServerShared;

std::string_view TargetOf(const http::request<http::string_body>& request) {
  return {request.target().data(), request.target().size()};
}

// The value of `key` in the target's query string ("/?token=abc&x=1"), empty when absent.
std::string QueryValue(std::string_view target, std::string_view key) {
  const std::size_t q = target.find('?');
  if (q == std::string_view::npos) return {};
  std::string_view query = target.substr(q + 1);
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const std::size_t eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == key) {
      return std::string(pair.substr(eq + 1));
    }
    if (amp == std::string_view::npos) break;
    query = query.substr(amp + 1);
  }
  return {};
}

bool TokenAccepted(const Shared& shared, const http::request<http::string_body>& request) {
  const std::string& token = shared.config.token;
  if (token.empty()) return true;
  if (QueryValue(TargetOf(request), "token") == token) return true;
  const auto authorization = request[http::field::authorization];
  return std::string_view(authorization.data(), authorization.size()) == "Bearer " + token;
}

bool OffersSubprotocol(const http::request<http::string_body>& request) {
  const auto header = request[http::field::sec_websocket_protocol];
  std::stringstream offered{std::string(header.data(), header.size())};
  std::string item;
  while (std::getline(offered, item, ',')) {
    const auto first = item.find_first_not_of(' ');
    const auto last = item.find_last_not_of(' ');
    if (first != std::string::npos && item.substr(first, last - first + 1) == kSubprotocol) {
      return true;
    }
  }
  return false;
}

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, Shared& shared)
      : ws_(std::move(socket)), shared_(shared),
        client_(std::make_shared<Client>(shared.config.queue)) {}

  ~WsSession() { shared_.registry.Remove(client_); }

  void Accept(http::request<http::string_body> request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
      response.set(http::field::sec_websocket_protocol, kSubprotocol);
      response.set(http::field::server, "dammloam-bridge");
    }));
    ws_.read_message_max(shared_.config.max_client_message);
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      self->OnAccept(ec);
    });
  }

 private:
  void OnAccept(beast::error_code ec) {
    if (ec) {
      spdlog::warn("bridge: WebSocket handshake failed: {}", ec.message());
      return;
    }
    std::weak_ptr<WsSession> weak = weak_from_this();
    auto executor = ws_.get_executor();
    client_->wake = [weak, executor] {
      if (auto self = weak.lock()) {
        if (!self->client_->writing.exchange(true)) {
          asio::post(executor, [self] { self->WriteNext(); });
        }
      }
    };
    const std::string session = "dammloam-bridge-" + std::to_string(shared_.next_session++);
    client_->queue.Push(TextFrame(ServerInfoJson("dammloam-bridge", session)));
    client_->queue.Push(TextFrame(shared_.advertise_json));
    shared_.registry.Add(client_);
    client_->wake();
    Read();
  }

  void Read() {
    ws_.async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      self->OnRead(ec);
    });
  }

  void OnRead(beast::error_code ec) {
    if (ec) {
      if (ec != websocket::error::closed) {
        spdlog::info("bridge: client closed: {}", ec.message());
      }
      closed_ = true;
      shared_.registry.Remove(client_);
      return;
    }
    if (ws_.got_binary()) {
      Refuse("binary client messages are not served (no clientPublish capability)");
    } else {
      Handle(beast::buffers_to_string(in_.data()));
    }
    in_.consume(in_.size());
    Read();
  }

  void Handle(const std::string& text) {
    const ClientRequest request = ParseClientText(text);
    if (const auto* subscribe = std::get_if<Subscribe>(&request)) {
      for (const auto& [id, channel] : subscribe->subscriptions) {
        const std::string error = client_->AddSubscription(id, channel, shared_.channel_ids);
        if (!error.empty()) Refuse(error);
      }
    } else if (const auto* unsubscribe = std::get_if<Unsubscribe>(&request)) {
      for (std::uint32_t id : unsubscribe->subscription_ids) {
        const std::string error = client_->RemoveSubscription(id);
        if (!error.empty()) Refuse(error);
      }
    } else if (const auto* unsupported = std::get_if<Unsupported>(&request)) {
      Refuse("op '" + unsupported->op + "' needs a capability this server does not offer");
    } else {
      Refuse(std::get<Malformed>(request).error);
    }
  }

  // Answers a bad request with a status error and keeps the connection.
  void Refuse(const std::string& why) {
    ++shared_.rejected;
    spdlog::warn("bridge: client request refused: {}", why);
    client_->queue.Push(TextFrame(StatusJson(StatusLevel::kError, why)));
    client_->wake();
  }

  // Runs on the I/O thread with client_->writing set.
  void WriteNext() {
    if (closed_) return;
    std::optional<Frame> frame = client_->queue.Pop();
    if (!frame) {
      client_->writing = false;
      // A push between Pop and the store above found writing set and did not wake us.
      if (client_->queue.frames() > 0 && !client_->writing.exchange(true)) {
        asio::post(ws_.get_executor(), [self = shared_from_this()] { self->WriteNext(); });
      }
      return;
    }
    current_ = std::move(*frame);
    ws_.binary(current_.binary);
    const std::array<asio::const_buffer, 2> buffers{
        asio::buffer(current_.prefix.data(), current_.prefix_size),
        asio::buffer(current_.payload->data(), current_.payload->size())};
    ws_.async_write(buffers, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->closed_ = true;  // writing stays set: nothing is posted to a dead session
        return;
      }
      self->WriteNext();
    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  Shared& shared_;
  std::shared_ptr<Client> client_;
  beast::flat_buffer in_;
  Frame current_;
  bool closed_ = false;
};

const char* ContentType(const std::string& name) {
  if (name.size() >= 5 && name.compare(name.size() - 5, 5, ".html") == 0) {
    return "text/html; charset=utf-8";
  }
  return "text/javascript; charset=utf-8";
}

// Reads one HTTP request: a WebSocket upgrade is handed to a WsSession, a GET of the page's
// files is answered, anything else gets an error status; then the connection closes.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Shared& shared) : stream_(std::move(socket)), shared_(shared) {}

  void Run() {
    parser_.body_limit(8 * 1024);
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) {
                       self->OnRead(ec);
                     });
  }

 private:
  void OnRead(beast::error_code ec) {
    if (ec) return;  // a client that sent no valid request: nothing to answer
    http::request<http::string_body> request = parser_.release();
    if (websocket::is_upgrade(request)) {
      if (!TokenAccepted(shared_, request)) return Reply(request, http::status::unauthorized,
                                                         "missing or wrong token\n");
      if (shared_.registry.clients() >= shared_.config.max_clients) {
        return Reply(request, http::status::service_unavailable,
                     "too many clients (--max-clients " +
                         std::to_string(shared_.config.max_clients) + ")\n");
      }
      if (!OffersSubprotocol(request)) {
        return Reply(request, http::status::bad_request,
                     std::string("WebSocket clients must offer subprotocol ") + kSubprotocol +
                         "\n");
      }
      stream_.expires_never();
      std::make_shared<WsSession>(stream_.release_socket(), shared_)->Accept(std::move(request));
      return;
    }
    if (request.method() != http::verb::get) {
      return Reply(request, http::status::method_not_allowed, "GET only\n");
    }
    const std::string_view target = TargetOf(request);
    std::string path(target.substr(0, target.find('?')));
    if (path == "/") path = "/index.html";
    if (path != "/index.html" && path != "/viewer.js") {
      return Reply(request, http::status::not_found, "not found\n");
    }
    std::ifstream file(shared_.config.web_root + path, std::ios::binary);
    if (!file) {
      return Reply(request, http::status::not_found,
                   "the page is not installed: no " + shared_.config.web_root + path + "\n");
    }
    std::stringstream body;
    body << file.rdbuf();
    Reply(request, http::status::ok, body.str(), ContentType(path));
  }

  void Reply(const http::request<http::string_body>& request, http::status status,
             std::string body, const char* type = "text/plain; charset=utf-8") {
    if (status != http::status::ok) ++shared_.rejected;
    auto response = std::make_shared<http::response<http::string_body>>(status, request.version());
    response->set(http::field::server, "dammloam-bridge");
    response->set(http::field::content_type, type);
    response->set(http::field::cache_control, "no-store");
    response->keep_alive(false);
    response->body() = std::move(body);
    response->prepare_payload();
    http::async_write(stream_, *response,
                      [self = shared_from_this(), response](beast::error_code, std::size_t) {
                        beast::error_code ignored;
                        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
                      });
  }

  beast::tcp_stream stream_;
  Shared& shared_;
  beast::flat_buffer buffer_;
  http::request_parser<http::string_body> parser_;
};

}  // namespace

struct WsServer::Impl {
  Shared shared;
  asio::io_context io{1};
  tcp::acceptor acceptor{io};
  std::thread thread;

  void Accept() {
    acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
      if (!ec) {
        std::make_shared<HttpSession>(std::move(socket), shared)->Run();
      } else if (ec == asio::error::operation_aborted) {
        return;
      } else {
        spdlog::warn("bridge: accept failed: {}", ec.message());
      }
      Accept();
    });
  }
};

WsServer::WsServer(const ServerConfig& config, std::vector<Channel> channels)
    : impl_(std::make_unique<Impl>()) {
  Shared& shared = impl_->shared;
  shared.config = config;
  shared.channels = std::move(channels);
  for (const Channel& c : shared.channels) shared.channel_ids.insert(c.id);
  shared.advertise_json = AdvertiseJson(shared.channels);

  beast::error_code ec;
  const auto address = asio::ip::make_address(config.address, ec);
  if (ec) throw std::runtime_error("--listen: '" + config.address + "' is not an IP address");
  const tcp::endpoint endpoint(address, config.port);
  auto& acceptor = impl_->acceptor;
  const auto fail = [&](const char* what) {
    throw std::runtime_error(std::string("cannot ") + what + " " + config.address + ":" +
                             std::to_string(config.port) + ": " + ec.message());
  };
  if (acceptor.open(endpoint.protocol(), ec); ec) fail("open a socket for");
  if (acceptor.set_option(asio::socket_base::reuse_address(true), ec); ec) fail("configure");
  if (acceptor.bind(endpoint, ec); ec) fail("listen on");
  if (acceptor.listen(asio::socket_base::max_listen_connections, ec); ec) fail("listen on");
  impl_->Accept();
  impl_->thread = std::thread([this] { impl_->io.run(); });
}

WsServer::~WsServer() {
  impl_->io.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

std::uint16_t WsServer::port() const { return impl_->acceptor.local_endpoint().port(); }

void WsServer::Publish(std::uint32_t channel_id, std::uint64_t timestamp_ns,
                       std::shared_ptr<const std::string> payload) {
  impl_->shared.registry.Publish(channel_id, timestamp_ns, payload);
}

bool WsServer::HasSubscribers(std::uint32_t channel_id) const {
  return impl_->shared.registry.HasSubscribers(channel_id);
}

ServerStats WsServer::Stats() const {
  const Shared& shared = impl_->shared;
  return {shared.registry.clients(), shared.registry.frames_dropped(),
          shared.registry.frames_queued(), shared.rejected.load()};
}

}  // namespace dammloam::bridge
