// How a link is tuned: Hello and command timeouts, resend periods, reconnection and reopening.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

#include "palpa/host/outcome.h"
#include "palpa/host/transport.h"

namespace palpa::host {

struct LinkOptions {
  int hello_timeout_ms = 50;  ///< Hello is resent this often until answered
  int hello_attempts = 60;
  int command_timeout_ms = 3000;
  bool reconnect = true;           ///< open a new session after a board reset
  size_t subscriber_queue = 8192;  ///< telemetry frames queued before the slowest drops some
  int stream_resend_ms = 50;       ///< resend a stream value not yet shown applied
  /// Close and Release are repeated until the board answers: once per retransmission timeout of
  /// the reliable commands (their measured round trip; 50 ms before the first), never more often
  /// than close_resend_ms. They are waited for while the board is heard (what was sent before
  /// them is still queued ahead: on a slow line, up to the board's receive buffer), and given
  /// up on after close_attempts resends of silence from the board or close_wait_max_ms in all.
  /// An unanswered Close leaves the board to its host-silence timeout, which ends the session as
  /// safely.
  int close_resend_ms = 20;
  int close_attempts = 10;
  int close_wait_max_ms = 2000;
  /// Opens the transport again after it was lost (a USB board unplugged and plugged back in):
  /// tried every reopen_interval_ms until it succeeds or the link is closed, then a new session
  /// opens as after a board reset. Empty: a lost transport ends the link. Device::Open sets it
  /// for usb:, hid: and serial: devices.
  std::function<Result<std::unique_ptr<Transport>>()> reopen;
  int reopen_interval_ms = 250;
};

}  // namespace palpa::host
