// A non-blocking TCP listening socket for the hosted boards' links and palpa-sim's truth channel.
#include "tcp_listener.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace palpa::hosted {

int ListenTcp(const std::string& spec, const char* option, std::string* address,
              std::string* error) {
  const std::string where = std::string(option) + " " + spec + ": ";
  const std::string rest = spec.substr(4);
  const size_t colon = rest.rfind(':');
  if (colon == std::string::npos) {
    *error = where + "expected tcp:HOST:PORT";
    return -1;
  }
  const std::string host = rest.substr(0, colon);
  char* end = nullptr;
  const long port = std::strtol(rest.c_str() + colon + 1, &end, 10);
  if (*end != '\0' || port < 0 || port > 65535 || colon + 1 == rest.size()) {
    *error = where + "the port must be a number from 0 to 65535";
    return -1;
  }
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  if (inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    *error = where + "'" + host + "' is not an IPv4 address";
    return -1;
  }
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  const int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 || listen(fd, 1) != 0) {
    *error = where + std::strerror(errno);
    close(fd);
    return -1;
  }
  socklen_t len = sizeof(addr);
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
  *address = "tcp:" + host + ":" + std::to_string(ntohs(addr.sin_port));
  return fd;
}

}  // namespace palpa::hosted
