// One WebSocket client: messages read within the size limit and handed to the API, answers and
// telemetry written in order (telemetry dropped while the client lags), and a ping every interval
// whose pongs tell the API the client is still there.
#pragma once

#include <deque>
#include <memory>
#include <string>

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "palpa/serve/api.h"

namespace palpa::serve {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;

class WsSession : public Peer, public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, Api& api, const ServeOptions& options, std::string description);
  /// Completes the upgrade the HTTP session read (and checked).
  void Start(http::request<http::string_body> request);

  void Send(std::string text) override;
  bool SendDroppable(std::string text) override;

 private:
  void Read();
  void OnRead(beast::error_code ec, size_t bytes);
  void Write();
  void Ping();
  void Close(websocket::close_code code, const std::string& why);
  void Gone(const std::string& why);

  websocket::stream<beast::tcp_stream> ws_;
  Api& api_;
  ServeOptions options_;
  std::string description_;
  ClientId id_ = 0;
  bool connected_ = false;
  beast::flat_buffer in_;
  size_t message_bytes_ = 0;  ///< of the message being read, dropped ones included
  bool too_large_ = false;
  std::deque<std::string> out_;
  bool writing_ = false;
  size_t queued_bytes_ = 0;
  boost::asio::steady_timer ping_timer_;
  PingWatch pings_;
  bool ping_in_flight_ = false;
  bool closing_ = false;
};

}  // namespace palpa::serve
