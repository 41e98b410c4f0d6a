// Who may reach the server: every HTTP request and WebSocket upgrade is checked here before it is
// served — its Host (no DNS-rebinding name), its Origin (no page from another site) and, on a
// non-loopback listener, the token printed at start.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/serve/serve_options.h"

namespace palpa::serve {

/// The parts of a request the guard looks at, as received (absent headers empty, has_origin false).
struct RequestFacts {
  std::string host;  ///< the Host header
  bool has_origin = false;
  std::string origin;         ///< the Origin header
  std::string target;         ///< "/websocket?token=...", the request target
  std::string cookie;         ///< the Cookie header
  std::string authorization;  ///< the Authorization header: "Bearer TOKEN" or "token TOKEN"
};

struct GuardVerdict {
  bool allowed = false;
  int http_status = 403;  ///< when refused: 400 (no Host), 401 (no or wrong token), 403
  std::string reason;     ///< in words, sent as the refusal's body and logged
  /// The token came in the URL: the answer sets it as a cookie so the page's own requests (its
  /// script, its WebSocket) carry it without putting it in every URL.
  bool set_token_cookie = false;
};

inline constexpr const char* kTokenCookie = "palpa_token";

class RequestGuard {
 public:
  /// `port`: the port actually bound (the listen port may have been 0).
  RequestGuard(const ServeOptions& options, uint16_t port);
  GuardVerdict Check(const RequestFacts& request) const;
  /// "host:port" names this server answers to, for messages.
  std::string AllowedHostsText() const;

 private:
  /// A Host header's or Origin's authority ("127.0.0.1:7180", "[::1]:7180", "localhost:7180").
  bool AuthorityAllowed(const std::string& authority) const;
  bool TokenMatches(const std::string& candidate) const;

  ServeOptions options_;
  uint16_t port_;
};

}  // namespace palpa::serve
