// A client of a running `palpa serve` (docs/serve.md): its JSON-RPC 2.0 API over a WebSocket
// (RFC 6455: text frames, masked, on a plain TCP socket), as the command line uses it for
// --device serve:HOST:PORT. A thread of its own reads every frame and answers the server's pings
// at once, so a client that waits (palpa set --hold) is never counted gone.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

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
  /// server's status line.
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

 private:
  explicit ServeClient(int fd);
  void Read();
  bool Send(uint8_t opcode, const std::string& payload);

  int fd_;
  std::mutex send_mutex_;
  std::mutex mutex_;  ///< guards what follows
  std::condition_variable arrived_;
  std::deque<nlohmann::json> answers_, notifications_;
  bool closed_ = false;
  int64_t next_id_ = 1;
  std::thread reader_;
};

}  // namespace palpa::host
