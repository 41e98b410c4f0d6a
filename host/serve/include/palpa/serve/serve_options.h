// What `palpa serve` listens on and whom it lets in: the address, the host names a page may use,
// the token a non-loopback listener requires, and the limits every client is held to.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "palpa/host/outcome.h"

namespace palpa::serve {

using host::Outcome;
using host::Result;

inline constexpr uint16_t kDefaultPort = 7180;

struct Endpoint {
  std::string address = "127.0.0.1";  ///< an IP literal, IPv6 without brackets
  uint16_t port = kDefaultPort;       ///< 0: any free port
  bool loopback = true;               ///< 127.0.0.0/8 or ::1
};

/// "127.0.0.1:7180", "[::1]:7180", "0.0.0.0:7180", "192.168.1.5:0" (0: any free port). Host names
/// are refused: the listener binds an address, and the Host check is made against it.
Result<Endpoint> ParseListen(const std::string& text);

/// 128 random bits as 32 hex digits, from the kernel's generator.
Result<std::string> NewToken();

/// The page's directory: installed beside the running program (BIN/../share/palpa/web), else the
/// source tree's (a build tree's program); empty when neither holds an index.html.
std::string DefaultWebRoot();

struct ServeOptions {
  std::string device_uri;
  Endpoint listen;
  /// Host names (besides IP literals and localhost) a page may reach the server by, for a lab
  /// machine's DNS name on a non-loopback listener (--allow-host).
  std::vector<std::string> allowed_hosts;
  /// Required on every request when the listener is not loopback; empty on loopback.
  std::string token;
  /// A simulator's truth side channel ("tcp:127.0.0.1:PORT"): each finger's true output goes out
  /// with the telemetry beside the estimate. Empty: none (a real board has no truth to tell).
  std::string truth_address;
  /// The page's directory; empty: the API only (GET / says so).
  std::string web_root;
  size_t max_message_bytes = 64 * 1024;  ///< larger messages get a JSON-RPC error, read and dropped
  size_t max_batch = 64;                 ///< calls in one JSON-RPC batch
  int ping_interval_ms = 100;            ///< the server pings every client this often
  int missed_pings_gone = 3;             ///< this many unanswered: the client is gone
};

}  // namespace palpa::serve
