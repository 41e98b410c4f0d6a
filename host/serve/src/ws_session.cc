// A WebSocket client of the server.
#include "ws_session.h"

#include <cstdio>

#include <boost/asio/post.hpp>

namespace palpa::serve {
namespace {

/// Beyond this much waiting to be written, telemetry is dropped for the client; beyond eight
/// times it, the client is closed (it does not read what it asked for).
constexpr size_t kQueueSoftBytes = 1 << 20;

}  // namespace

WsSession::WsSession(tcp::socket socket, Api& api, const ServeOptions& options,
                     std::string description)
    : ws_(std::move(socket)),
      api_(api),
      options_(options),
      description_(std::move(description)),
      ping_timer_(ws_.get_executor()),
      pings_(options.missed_pings_gone) {}

void WsSession::Start(http::request<http::string_body> request) {
  // The server's own pings decide when a client is gone; no idle timeout of Beast's.
  websocket::stream_base::timeout timeout{};
  timeout.handshake_timeout = std::chrono::seconds(5);
  timeout.idle_timeout = websocket::stream_base::none();
  timeout.keep_alive_pings = false;
  ws_.set_option(timeout);
  // Past the API's limit a message is read and dropped piece by piece; this only bounds how long
  // a client may go on sending one.
  ws_.read_message_max(64u << 20);
  ws_.auto_fragment(false);
  ws_.control_callback([this](websocket::frame_type kind, beast::string_view payload) {
    if (kind != websocket::frame_type::pong) return;
    uint64_t seq = 0;
    for (char c : payload) {
      if (c < '0' || c > '9') return;
      seq = seq * 10 + static_cast<uint64_t>(c - '0');
    }
    pings_.Pong(seq);
  });
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return;
    self->id_ = self->api_.Connect(self, self->description_);
    self->connected_ = true;
    self->Read();
    self->Ping();
  });
}

void WsSession::Read() {
  ws_.async_read_some(
      in_, 16 * 1024,
      [self = shared_from_this()](beast::error_code ec, size_t bytes) { self->OnRead(ec, bytes); });
}

void WsSession::OnRead(beast::error_code ec, size_t bytes) {
  if (ec) return Gone(ec == websocket::error::closed ? "closed" : "disconnected: " + ec.message());
  message_bytes_ += bytes;
  if (message_bytes_ > options_.max_message_bytes) {
    too_large_ = true;
    in_.consume(in_.size());  // dropped as it comes: memory stays bounded
  }
  if (!ws_.is_message_done()) return Read();
  if (too_large_) {
    api_.OnTooLarge(id_, message_bytes_);
  } else if (!ws_.got_text()) {
    api_.OnBinary(id_);
  } else {
    const auto data = in_.data();
    api_.OnMessage(id_, std::string_view(static_cast<const char*>(data.data()), data.size()));
  }
  in_.consume(in_.size());
  message_bytes_ = 0;
  too_large_ = false;
  if (!closing_) Read();
}

void WsSession::Send(std::string text) {
  if (closing_) return;
  queued_bytes_ += text.size();
  out_.push_back(std::move(text));
  if (queued_bytes_ > 8 * kQueueSoftBytes) {
    // Closed from the server's loop, not from inside the API call that is sending (which may be
    // going through every client): the API never sees a client vanish under its feet.
    closing_ = true;
    boost::asio::post(ws_.get_executor(), [self = shared_from_this()] {
      self->closing_ = false;
      self->Close(websocket::close_code::policy_error, "does not read what it is sent");
    });
    return;
  }
  Write();
}

bool WsSession::SendDroppable(std::string text) {
  if (queued_bytes_ > kQueueSoftBytes || closing_) return false;
  Send(std::move(text));
  return true;
}

void WsSession::Write() {
  if (writing_ || out_.empty()) return;
  writing_ = true;
  ws_.text(true);
  ws_.async_write(boost::asio::buffer(out_.front()),
                  [self = shared_from_this()](beast::error_code ec, size_t) {
                    self->writing_ = false;
                    if (ec) return;  // the read side notices and says why
                    self->queued_bytes_ -= self->out_.front().size();
                    self->out_.pop_front();
                    self->Write();
                  });
}

void WsSession::Ping() {
  ping_timer_.expires_after(std::chrono::milliseconds(options_.ping_interval_ms));
  ping_timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (ec || self->closing_) return;
    uint64_t seq = 0;
    if (self->pings_.Due(seq)) {
      return self->Close(websocket::close_code::going_away,
                         std::to_string(self->pings_.missed()) + " pings unanswered");
    }
    if (!self->ping_in_flight_) {  // one ping in flight at a time; a stuck one counts as missed
      self->ping_in_flight_ = true;
      const std::string payload = std::to_string(seq);
      self->ws_.async_ping(websocket::ping_data(payload.c_str()),
                           [self](beast::error_code) { self->ping_in_flight_ = false; });
    }
    self->Ping();
  });
}

void WsSession::Close(websocket::close_code code, const std::string& why) {
  if (closing_) return;
  Gone(why);
  closing_ = true;
  ping_timer_.cancel();
  // The socket is shut at once: a client that stopped answering is not waited for.
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
  beast::get_lowest_layer(ws_).close();
  (void)code;
}

void WsSession::Gone(const std::string& why) {
  if (!connected_) return;
  connected_ = false;
  ping_timer_.cancel();
  api_.Disconnect(id_, why);
}

}  // namespace palpa::serve
