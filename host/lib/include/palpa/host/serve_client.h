// A client of a running `palpa serve` (docs/serve.md): its JSON-RPC 2.0 API over a WebSocket
// (RFC 6455 on a plain TCP socket, Boost.Beast's client: the upgrade's answer is verified, frames
// are masked and bounded), as the command line uses it for --device serve:HOST:PORT. A thread of
// its own reads every frame and answers the server's pings at once, so a client that waits
// (palpa set --hold) is never counted gone.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

#include "palpa/host/outcome.h"

namespace palpa::host {

/// "serve:HOST:PORT" or "serve:HOST:PORT?token=T" (a non-loopback server's token).
struct ServeAddress {
  std::string host;
  uint16_t port = 0;
  std::string token;
};
Result<ServeAddress> ParseServeUri(const std::string& uri);

class ServeClient {
 public:
  /// Connects and upgrades to the WebSocket; a refusal (a wrong token, a foreign Host) says the
  /// server's status line, an answer that is not a WebSocket upgrade (no 101, no Upgrade or
  /// Connection header, a wrong Sec-WebSocket-Accept) says what was wrong with it.
  static Result<std::unique_ptr<ServeClient>> Connect(const std::string& uri);
  ~ServeClient();
  ServeClient(const ServeClient&) = delete;
  ServeClient& operator=(const ServeClient&) = delete;

  /// One call and its result. An error answer is an Outcome: the status its data names
  /// (kBusy when another client controls the board), the server's message, the faults it lists.
  Result<nlohmann::json> Call(const std::string& method,
                              const nlohmann::json& params = nlohmann::json::object(),
                              double timeout_s = 30);
  /// The next notification ({"method", "params"}) within `timeout_s`; false when none came or
  /// the connection closed (closed() says which).
  bool NextNotification(nlohmann::json& out, double timeout_s);
  bool closed();
  /// Hands each notification to `handler` on the reader thread as it arrives (keep it short);
  /// one it returns true for is not queued for NextNotification.
  void OnNotification(std::function<bool(const nlohmann::json&)> handler);

 private:
  struct Impl;  ///< the socket and its thread, on Boost.Beast (which stays out of this header)
  ServeClient();
  bool Send(std::string text);
  void Arrived(const std::string& text);
  void Ended();

  std::unique_ptr<Impl> impl_;
  std::mutex mutex_;  ///< guards what follows
  std::condition_variable arrived_;
  std::deque<nlohmann::json> answers_, notifications_;
  std::shared_ptr<const std::function<bool(const nlohmann::json&)>> handler_;
  bool closed_ = false;
  int64_t next_id_ = 1;
};

}  // namespace palpa::host
