// The shared line: a poll loop relaying whole frames from hosts to the board, and every byte from
// the board to every host.
#include "shared_line.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <vector>

namespace palpa::testing {
namespace {

void NoDelay(int fd) {
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
}

void WriteAll(int fd, const uint8_t* data, size_t size) {
  while (size > 0) {
    const ssize_t n = send(fd, data, size, MSG_NOSIGNAL);
    if (n <= 0) return;  // a host that went away: the poll loop drops it
    data += n;
    size -= static_cast<size_t>(n);
  }
}

}  // namespace

bool SharedLine::Start(const std::string& board_address, int host_bytes_per_second) {
  rate_ = host_bytes_per_second;
  const int port = std::atoi(board_address.c_str() + board_address.rfind(':') + 1);
  board_fd_ = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<uint16_t>(port));
  if (connect(board_fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) return false;
  NoDelay(board_fd_);
  listen_fd_ = socket(AF_INET, SOCK_STREAM, 0);
  a.sin_port = 0;
  socklen_t size = sizeof(a);
  if (bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0 ||
      listen(listen_fd_, 8) != 0 ||
      getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &size) != 0) {
    return false;
  }
  address_ = "tcp:127.0.0.1:" + std::to_string(ntohs(a.sin_port));
  thread_ = std::thread(&SharedLine::Run, this);
  return true;
}

SharedLine::~SharedLine() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (listen_fd_ >= 0) close(listen_fd_);
  if (board_fd_ >= 0) close(board_fd_);
}

void SharedLine::Run() {
  struct Host {
    int fd;
    std::vector<uint8_t> partial;  ///< a frame not yet ended by its delimiter
  };
  std::vector<Host> hosts;
  uint8_t buffer[4096];
  bool board_gone = false;
  // What the board sends goes on to every host (false once the board went away).
  auto from_board = [&] {
    const ssize_t n = read(board_fd_, buffer, sizeof(buffer));
    if (n <= 0) return false;
    for (const Host& h : hosts) WriteAll(h.fd, buffer, static_cast<size_t>(n));
    return true;
  };
  // A slow line is full duplex, as a UART is: while a host's frame takes its time, the board's
  // answers keep coming back.
  auto carry_board_until = [&](std::chrono::steady_clock::time_point end) {
    for (auto now = std::chrono::steady_clock::now(); now < end && !board_gone;
         now = std::chrono::steady_clock::now()) {
      pollfd board{board_fd_, POLLIN, 0};
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - now).count();
      if (poll(&board, 1, static_cast<int>(left) + 1) > 0 && !from_board()) board_gone = true;
    }
  };
  while (!stop_ && !board_gone) {
    std::vector<pollfd> fds = {{board_fd_, POLLIN, 0}, {listen_fd_, POLLIN, 0}};
    for (const Host& h : hosts) fds.push_back({h.fd, POLLIN, 0});
    if (poll(fds.data(), fds.size(), 20) <= 0) continue;
    if (fds[0].revents != 0 && !from_board()) break;  // the board went away
    if (fds[1].revents != 0) {
      const int fd = accept(listen_fd_, nullptr, nullptr);
      if (fd >= 0) {
        NoDelay(fd);
        hosts.push_back({fd, {}});
      }
    }
    for (size_t i = 0; i + 2 < fds.size(); ++i) {  // the hosts polled (not one accepted now)
      if (fds[2 + i].revents == 0) continue;
      uint8_t input[4096];
      const ssize_t n = read(hosts[i].fd, input, sizeof(input));
      if (n <= 0) {
        close(hosts[i].fd);
        hosts[i].fd = -1;
        continue;
      }
      for (ssize_t k = 0; k < n; ++k) {
        hosts[i].partial.push_back(input[k]);
        if (input[k] != 0) continue;
        WriteAll(board_fd_, hosts[i].partial.data(), hosts[i].partial.size());
        if (rate_ > 0) {
          carry_board_until(std::chrono::steady_clock::now() +
                            std::chrono::microseconds(
                                static_cast<int64_t>(hosts[i].partial.size()) * 1000000 / rate_));
        }
        hosts[i].partial.clear();
      }
    }
    std::erase_if(hosts, [](const Host& h) { return h.fd < 0; });
  }
  for (const Host& h : hosts) close(h.fd);
}

}  // namespace palpa::testing
