// Listening addresses and tokens for `palpa serve`.
#include "palpa/serve/serve_options.h"

#include <arpa/inet.h>
#include <sys/random.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <fstream>

namespace palpa::serve {

Result<Endpoint> ParseListen(const std::string& text) {
  const auto invalid = [&](const std::string& why) {
    return Outcome::Fail(host::Status::kInvalidArgument, "--listen '" + text + "': " + why);
  };
  Endpoint e;
  std::string port;
  if (!text.empty() && text[0] == '[') {
    const size_t close = text.find(']');
    if (close == std::string::npos || close + 1 >= text.size() || text[close + 1] != ':')
      return invalid("expected [IPv6]:PORT");
    e.address = text.substr(1, close - 1);
    port = text.substr(close + 2);
  } else {
    const size_t colon = text.rfind(':');
    if (colon == std::string::npos || text.find(':') != colon)
      return invalid("expected ADDRESS:PORT, e.g. 127.0.0.1:7180 ([::1]:7180 for IPv6)");
    e.address = text.substr(0, colon);
    port = text.substr(colon + 1);
  }
  if (port.empty() || port.size() > 5 ||
      port.find_first_not_of("0123456789") != std::string::npos || std::stoul(port) > 65535)
    return invalid("the port must be a whole number from 0 (any free port) to 65535");
  e.port = static_cast<uint16_t>(std::stoul(port));
  in_addr v4{};
  in6_addr v6{};
  if (inet_pton(AF_INET, e.address.c_str(), &v4) == 1) {
    e.loopback = (ntohl(v4.s_addr) >> 24) == 127;
  } else if (inet_pton(AF_INET6, e.address.c_str(), &v6) == 1) {
    e.loopback = IN6_IS_ADDR_LOOPBACK(&v6);
  } else {
    return invalid("'" + e.address +
                   "' is not an IP address (the listener binds an address; name the host a "
                   "page uses with --allow-host)");
  }
  return e;
}

Result<std::string> NewToken() {
  unsigned char bytes[16];
  if (getrandom(bytes, sizeof(bytes), 0) != static_cast<ssize_t>(sizeof(bytes)))
    return Outcome::Fail(host::Status::kUnavailable, "no random bytes from the kernel for a token");
  std::string hex;
  char two[3];
  for (unsigned char b : bytes) {
    std::snprintf(two, sizeof(two), "%02x", b);
    hex += two;
  }
  return hex;
}

std::string DefaultWebRoot() {
  char exe[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
  std::vector<std::string> candidates;
  if (n > 0) {
    std::string dir(exe, static_cast<size_t>(n));
    dir = dir.substr(0, dir.rfind('/'));
    candidates.push_back(dir + "/../" PALPA_WEB_INSTALL_PATH);
  }
  candidates.push_back(PALPA_WEB_SOURCE_PATH);
  for (const std::string& c : candidates) {
    if (std::ifstream(c + "/index.html").good()) return c;
  }
  return "";
}

}  // namespace palpa::serve
