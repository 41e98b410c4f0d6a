// palpa serve's API from C++: Boost.Beast's WebSocket client (the upgrade verified, frames masked
// and bounded, pings answered) on a thread of its own; calls answered by id, notifications queued.
#include "palpa/host/serve_client.h"

#include <cctype>
#include <chrono>
#include <deque>
#include <future>
#include <optional>
#include <thread>
#include <utility>

#include "palpa/host/bit_names.h"

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

namespace palpa::host {
namespace {

using nlohmann::json;
namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;

/// Notifications kept for a reader that does not take them (telemetry it did not ask for).
constexpr size_t kMaxQueuedNotifications = 4096;
/// Beyond anything the server sends (a study's report is the largest answer): a bigger message
/// closes the connection instead of growing without bound.
constexpr size_t kMaxMessageBytes = 64u << 20;
/// Connecting, the upgrade and the closing handshake each get this long.
constexpr auto kHandshakeTimeout = std::chrono::seconds(10);

Status StatusNamed(const std::string& name) {
  for (unsigned i = 0; i < static_cast<unsigned>(Status::kCount); ++i) {
    if (name == protocol::kStatusNames[i]) return static_cast<Status>(i);
  }
  return Status::kUnavailable;
}

}  // namespace

Result<ServeAddress> ParseServeUri(const std::string& uri) {
  const std::string bad = uri + ": expected serve:HOST:PORT[?token=T] (palpa serve's address)";
  if (uri.rfind("serve:", 0) != 0) return {Status::kInvalidArgument, bad};
  std::string rest = uri.substr(6);
  ServeAddress a;
  if (const size_t q = rest.find('?'); q != std::string::npos) {
    const std::string query = rest.substr(q + 1);
    if (query.rfind("token=", 0) != 0) return {Status::kInvalidArgument, bad};
    a.token = query.substr(6);
    rest.resize(q);
  }
  const size_t colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0) return {Status::kInvalidArgument, bad};
  a.host = rest.substr(0, colon);
  if (a.host.size() > 2 && a.host.front() == '[' && a.host.back() == ']')
    a.host = a.host.substr(1, a.host.size() - 2);
  const std::string port = rest.substr(colon + 1);
  if (port.empty() || port.size() > 5 ||
      port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) < 1 ||
      std::stoi(port) > 65535)
    return {Status::kInvalidArgument, bad};
  a.port = static_cast<uint16_t>(std::stoi(port));
  for (char c : a.token) {
    if (!std::isalnum(static_cast<unsigned char>(c)))
      return {Status::kInvalidArgument, uri + ": the token is letters and digits"};
  }
  return a;
}

/// Every operation on the socket runs on the io_context's one thread, as Beast requires; other
/// threads hand it writes and wait for their outcome.
struct ServeClient::Impl {
  explicit Impl(ServeClient& client) : owner(client) {}

  /// Reads messages until the connection ends; Beast answers pings and close frames meanwhile.
  void ReadNext() {
    ws.async_read(incoming, [this](beast::error_code ec, size_t) {
      if (ec) {
        open = false;
        owner.Ended();
        return;
      }
      if (ws.got_text()) owner.Arrived(beast::buffers_to_string(incoming.data()));
      incoming.consume(incoming.size());
      ReadNext();
    });
  }

  /// One write in flight at a time (Beast's rule); the rest wait in order.
  void Queue(std::string text, std::promise<bool> sent) {
    if (!open) return sent.set_value(false);
    outgoing.emplace_back(std::move(text), std::move(sent));
    if (outgoing.size() == 1) WriteFront();
  }

  void WriteFront() {
    ws.async_write(net::buffer(outgoing.front().first), [this](beast::error_code ec, size_t) {
      outgoing.front().second.set_value(!ec);
      outgoing.pop_front();
      if (ec) open = false;
      for (; !open && !outgoing.empty(); outgoing.pop_front())
        outgoing.front().second.set_value(false);
      if (!outgoing.empty()) WriteFront();
    });
  }

  ServeClient& owner;
  net::io_context io;
  std::optional<net::executor_work_guard<net::io_context::executor_type>> work;
  websocket::stream<beast::tcp_stream> ws{io};
  beast::flat_buffer incoming;
  std::deque<std::pair<std::string, std::promise<bool>>> outgoing;
  bool open = false;
  std::thread thread;
};

Result<std::unique_ptr<ServeClient>> ServeClient::Connect(const std::string& uri) {
  const auto address = ParseServeUri(uri);
  if (!address.ok()) return address.outcome();
  const ServeAddress& a = address.value;
  std::unique_ptr<ServeClient> client(new ServeClient());
  Impl& s = *client->impl_;
  const std::string port = std::to_string(a.port);
  beast::error_code ec;
  const auto endpoints = net::ip::tcp::resolver(s.io).resolve(a.host, port, ec);
  if (ec) return {Status::kNotFound, uri + ": " + ec.message()};

  const std::string authority =
      (a.host.find(':') != std::string::npos ? "[" + a.host + "]" : a.host) + ":" + port;
  const std::string target = "/websocket" + (a.token.empty() ? "" : "?token=" + a.token);
  websocket::stream_base::timeout timeouts =
      websocket::stream_base::timeout::suggested(beast::role_type::client);
  timeouts.handshake_timeout = kHandshakeTimeout;  // the server's pings watch an open connection
  s.ws.set_option(timeouts);
  s.ws.read_message_max(kMaxMessageBytes);
  websocket::response_type response;
  bool connected = false, done = false;
  s.ws.next_layer().expires_after(kHandshakeTimeout);
  s.ws.next_layer().async_connect(endpoints, [&](beast::error_code e, const auto&) {
    ec = e;
    done = static_cast<bool>(e);
    if (e) return;
    connected = true;
    s.ws.next_layer().expires_never();  // the handshake has its own timeout from here
    s.ws.async_handshake(response, authority, target, [&](beast::error_code h) {
      ec = h;
      done = true;
    });
  });
  // Until the upgrade's outcome, not until the io_context runs dry: a refused upgrade leaves
  // Beast's handshake timer to expire on its own.
  while (!done && s.io.run_one() > 0) {
  }
  s.io.restart();
  if (!connected) {
    return {
        Status::kUnavailable,
        uri + (ec == beast::error::timeout ? ": no answer to connecting within 10 s"
                                           : ": nothing listens there (is palpa serve running?)")};
  }
  if (ec == websocket::error::upgrade_declined) {
    return {Status::kUnavailable, uri + ": palpa serve refused the connection (HTTP/" +
                                      std::to_string(response.version() / 10) + "." +
                                      std::to_string(response.version() % 10) + " " +
                                      std::to_string(response.result_int()) + " " +
                                      std::string(response.reason()) + ")"};
  }
  if (ec == beast::error::timeout)
    return {Status::kTimeout, uri + ": no answer to the WebSocket upgrade within 10 s"};
  if (ec) {
    return {Status::kUnavailable,
            uri + ": not a WebSocket upgrade (is palpa serve listening there?): " + ec.message()};
  }
  s.ws.text(true);  // JSON-RPC's messages are text
  s.open = true;
  s.work.emplace(s.io.get_executor());
  s.ReadNext();
  s.thread = std::thread([&s] { s.io.run(); });
  return client;
}

ServeClient::ServeClient() : impl_(std::make_unique<Impl>(*this)) {}

ServeClient::~ServeClient() {
  Impl& s = *impl_;
  if (!s.thread.joinable()) return;
  net::post(s.io, [&s] {
    // The closing handshake, then the socket closed whatever its outcome; the reader ends too.
    if (s.open) {
      s.ws.async_close(websocket::close_code::normal, [&s](beast::error_code) {
        beast::error_code ignored;
        s.ws.next_layer().socket().close(ignored);
      });
    }
    s.work.reset();
  });
  s.thread.join();
}

bool ServeClient::Send(std::string text) {
  std::promise<bool> sent;
  std::future<bool> outcome = sent.get_future();
  net::post(impl_->io, [&s = *impl_, text = std::move(text), sent = std::move(sent)]() mutable {
    s.Queue(std::move(text), std::move(sent));
  });
  return outcome.get();
}

void ServeClient::OnNotification(std::function<bool(const json&)> handler) {
  std::lock_guard<std::mutex> lock(mutex_);
  handler_ = std::make_shared<const std::function<bool(const json&)>>(std::move(handler));
}

void ServeClient::Arrived(const std::string& text) {
  json m = json::parse(text, nullptr, false);
  if (!m.is_object()) return;
  std::unique_lock<std::mutex> lock(mutex_);
  if (!m.contains("id") && handler_ != nullptr) {
    const auto handler = handler_;  // called unlocked: it may take its own locks
    lock.unlock();
    if ((*handler)(m)) return;
    lock.lock();
  }
  if (m.contains("id")) {
    answers_.push_back(std::move(m));
  } else {
    if (notifications_.size() >= kMaxQueuedNotifications) notifications_.pop_front();
    notifications_.push_back(std::move(m));
  }
  arrived_.notify_all();
}

void ServeClient::Ended() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  arrived_.notify_all();
}

bool ServeClient::closed() {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

Result<json> ServeClient::Call(const std::string& method, const json& params, double timeout_s) {
  int64_t id = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    id = next_id_++;
  }
  const json request = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}};
  if (!Send(request.dump())) return {Status::kIoError, method + ": palpa serve went away"};
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    for (auto it = answers_.begin(); it != answers_.end(); ++it) {
      if ((*it)["id"] != id) continue;
      json answer = std::move(*it);
      answers_.erase(it);
      if (answer.contains("result")) return answer["result"];
      const json& e = answer.value("error", json::object());
      const json& data = e.value("data", json::object());
      Outcome o;
      const int code = e.value("code", 0);
      o.status =
          data.contains("status") && data["status"].is_string()
              ? StatusNamed(data["status"].get<std::string>())
              : (code == -32001 || code == -32002 ? Status::kBusy : Status::kInvalidArgument);
      o.message = e.value("message", std::string("refused"));
      std::vector<std::string> faults;  // the faults it was refused for, by name
      for (const json& f : data.is_object() ? data.value("faults", json::array()) : json::array())
        if (f.is_string()) faults.push_back(f.get<std::string>());
      o.faults = FaultBitmap(faults);
      return o;
    }
    if (closed_) return {Status::kIoError, method + ": palpa serve closed the connection"};
    if (arrived_.wait_until(lock, deadline) == std::cv_status::timeout)
      return {Status::kTimeout, method + ": no answer from palpa serve"};
  }
}

bool ServeClient::NextNotification(json& out, double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (notifications_.empty() && !closed_) {
    if (arrived_.wait_until(lock, deadline) == std::cv_status::timeout) break;
  }
  if (notifications_.empty()) return false;
  out = std::move(notifications_.front());
  notifications_.pop_front();
  return true;
}

}  // namespace palpa::host
