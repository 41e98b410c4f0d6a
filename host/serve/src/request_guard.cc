// The checks every request passes: Host, Origin, token.
#include "palpa/serve/request_guard.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>

namespace palpa::serve {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool IsLoopbackLiteral(const std::string& name) {
  in_addr v4{};
  in6_addr v6{};
  if (inet_pton(AF_INET, name.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  return inet_pton(AF_INET6, name.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

bool IsIpLiteral(const std::string& name) {
  in_addr v4{};
  in6_addr v6{};
  return inet_pton(AF_INET, name.c_str(), &v4) == 1 || inet_pton(AF_INET6, name.c_str(), &v6) == 1;
}

/// The value of `key` in a query string or a cookie header ("a=1&token=x", "a=1; palpa_token=x").
std::string FindValue(const std::string& text, const std::string& key, char separator) {
  size_t at = 0;
  while (at <= text.size()) {
    size_t end = text.find(separator, at);
    if (end == std::string::npos) end = text.size();
    std::string part = text.substr(at, end - at);
    while (!part.empty() && part.front() == ' ') part.erase(part.begin());
    if (part.compare(0, key.size() + 1, key + "=") == 0) return part.substr(key.size() + 1);
    at = end + 1;
  }
  return "";
}

}  // namespace

RequestGuard::RequestGuard(const ServeOptions& options, uint16_t port)
    : options_(options), port_(port) {
  for (std::string& h : options_.allowed_hosts) h = Lower(h);
}

bool RequestGuard::AuthorityAllowed(const std::string& authority) const {
  std::string name, port;
  if (!authority.empty() && authority[0] == '[') {
    const size_t close = authority.find(']');
    if (close == std::string::npos) return false;
    name = authority.substr(1, close - 1);
    if (close + 1 < authority.size()) {
      if (authority[close + 1] != ':') return false;
      port = authority.substr(close + 2);
    }
    if (!IsIpLiteral(name) || name.find(':') == std::string::npos) return false;
  } else {
    const size_t colon = authority.find(':');
    name = authority.substr(0, colon);
    if (colon != std::string::npos) port = authority.substr(colon + 1);
  }
  // Browsers leave out the scheme's default port; this server never listens on port 80 by default.
  const std::string expected_port = std::to_string(port_);
  if (port.empty() ? port_ != 80 : port != expected_port) return false;
  name = Lower(name);
  if (name.empty()) return false;
  if (name == "localhost" || IsLoopbackLiteral(name)) return true;
  // A loopback listener is reached only through loopback: any other name is a DNS-rebinding
  // attempt or a mistake. Elsewhere an IP literal cannot be rebound; a name must be allowed.
  if (options_.listen.loopback) return false;
  if (IsIpLiteral(name)) return true;
  return std::find(options_.allowed_hosts.begin(), options_.allowed_hosts.end(), name) !=
         options_.allowed_hosts.end();
}

bool RequestGuard::TokenMatches(const std::string& candidate) const {
  const std::string& token = options_.token;
  if (candidate.size() != token.size()) return false;
  unsigned char difference = 0;  // every byte compared: the time says nothing of the token
  for (size_t i = 0; i < token.size(); ++i)
    difference |= static_cast<unsigned char>(candidate[i] ^ token[i]);
  return difference == 0;
}

std::string RequestGuard::AllowedHostsText() const {
  std::string text = "localhost:" + std::to_string(port_) + ", 127.0.0.1:" + std::to_string(port_);
  if (!options_.listen.loopback) {
    text += ", any IP address:" + std::to_string(port_);
    for (const std::string& h : options_.allowed_hosts)
      text += ", " + h + ":" + std::to_string(port_);
  }
  return text;
}

GuardVerdict RequestGuard::Check(const RequestFacts& r) const {
  GuardVerdict v;
  if (r.host.empty()) {
    v.http_status = 400;
    v.reason = "no Host header";
    return v;
  }
  if (!AuthorityAllowed(r.host)) {
    v.reason =
        "Host '" + r.host + "' is not this server (it answers to " + AllowedHostsText() + ")";
    return v;
  }
  if (r.has_origin) {
    const std::string origin = Lower(r.origin);
    const std::string scheme = "http://";
    if (origin.compare(0, scheme.size(), scheme) != 0 ||
        !AuthorityAllowed(origin.substr(scheme.size()))) {
      v.reason =
          "Origin '" + r.origin + "' is another site: pages from elsewhere may not use this server";
      return v;
    }
  }
  if (!options_.token.empty()) {
    const size_t query = r.target.find('?');
    const std::string from_url =
        query == std::string::npos ? "" : FindValue(r.target.substr(query + 1), "token", '&');
    std::string from_header;
    for (const char* scheme : {"Bearer ", "token "}) {
      if (r.authorization.compare(0, std::string(scheme).size(), scheme) == 0)
        from_header = r.authorization.substr(std::string(scheme).size());
    }
    const std::string from_cookie = FindValue(r.cookie, kTokenCookie, ';');
    if (TokenMatches(from_url)) {
      v.set_token_cookie = true;
    } else if (!TokenMatches(from_header) && !TokenMatches(from_cookie)) {
      v.http_status = 401;
      v.reason = from_url.empty() && from_header.empty() && from_cookie.empty()
                     ? "this server listens beyond loopback and needs the token it printed at "
                       "start (?token=... in the URL)"
                     : "wrong token";
      return v;
    }
  }
  v.allowed = true;
  return v;
}

}  // namespace palpa::serve
