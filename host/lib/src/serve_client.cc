// palpa serve's API from C++: the WebSocket handshake and frames by hand on a TCP socket (the
// host library has no WebSocket dependency), calls answered by id, notifications queued.
#include "palpa/host/serve_client.h"

#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <random>

namespace palpa::host {
namespace {

using nlohmann::json;

/// Notifications kept for a reader that does not take them (telemetry it did not ask for).
constexpr size_t kMaxQueuedNotifications = 4096;

std::string Base64(const std::string& in) {
  static const char* const kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = static_cast<uint8_t>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<uint32_t>(static_cast<uint8_t>(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= static_cast<uint8_t>(in[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < in.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

std::string RandomBytes(size_t n) {
  static std::random_device device;
  std::string out(n, '\0');
  for (char& c : out) c = static_cast<char>(device() & 0xff);
  return out;
}

bool ReadExactly(int fd, void* data, size_t n) {
  auto* p = static_cast<uint8_t*>(data);
  while (n > 0) {
    const ssize_t got = ::recv(fd, p, n, 0);
    if (got <= 0) return false;
    p += got;
    n -= static_cast<size_t>(got);
  }
  return true;
}

Status StatusNamed(const std::string& name) {
  for (unsigned i = 0; i < static_cast<unsigned>(Status::kCount); ++i) {
    if (name == protocol::kStatusNames[i]) return static_cast<Status>(i);
  }
  return Status::kUnavailable;
}

}  // namespace

Result<ServeAddress> ParseServeUri(const std::string& uri) {
  const std::string bad = uri + ": expected serve:HOST:PORT[?token=T] (palpa serve's address)";
  if (uri.rfind("serve:", 0) != 0) return {Status::kInvalidArgument, bad};
  std::string rest = uri.substr(6);
  ServeAddress a;
  if (const size_t q = rest.find('?'); q != std::string::npos) {
    const std::string query = rest.substr(q + 1);
    if (query.rfind("token=", 0) != 0) return {Status::kInvalidArgument, bad};
    a.token = query.substr(6);
    rest.resize(q);
  }
  const size_t colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0) return {Status::kInvalidArgument, bad};
  a.host = rest.substr(0, colon);
  if (a.host.size() > 2 && a.host.front() == '[' && a.host.back() == ']')
    a.host = a.host.substr(1, a.host.size() - 2);
  const std::string port = rest.substr(colon + 1);
  if (port.empty() || port.size() > 5 ||
      port.find_first_not_of("0123456789") != std::string::npos || std::stoi(port) < 1 ||
      std::stoi(port) > 65535)
    return {Status::kInvalidArgument, bad};
  a.port = static_cast<uint16_t>(std::stoi(port));
  for (char c : a.token) {
    if (!std::isalnum(static_cast<unsigned char>(c)))
      return {Status::kInvalidArgument, uri + ": the token is letters and digits"};
  }
  return a;
}

Result<std::unique_ptr<ServeClient>> ServeClient::Connect(const std::string& uri) {
  const auto address = ParseServeUri(uri);
  if (!address.ok()) return address.outcome();
  const ServeAddress& a = address.value;
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(a.port);
  if (const int e = ::getaddrinfo(a.host.c_str(), port.c_str(), &hints, &found); e != 0)
    return {Status::kNotFound, uri + ": " + ::gai_strerror(e)};
  int fd = -1;
  for (addrinfo* p = found; p != nullptr && fd < 0; p = p->ai_next) {
    fd = ::socket(p->ai_family, p->ai_socktype, p->ai_protocol);
    if (fd >= 0 && ::connect(fd, p->ai_addr, p->ai_addrlen) != 0) {
      ::close(fd);
      fd = -1;
    }
  }
  ::freeaddrinfo(found);
  if (fd < 0)
    return {Status::kUnavailable, uri + ": nothing listens there (is palpa serve running?)"};
  const std::string authority =
      (a.host.find(':') != std::string::npos ? "[" + a.host + "]" : a.host) + ":" + port;
  const std::string request =
      "GET /websocket" + (a.token.empty() ? "" : "?token=" + a.token) +
      " HTTP/1.1\r\nHost: " + authority +
      "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: " +
      Base64(RandomBytes(16)) + "\r\nSec-WebSocket-Version: 13\r\n\r\n";
  std::string head;
  bool sent = ::send(fd, request.data(), request.size(), MSG_NOSIGNAL) ==
              static_cast<ssize_t>(request.size());
  for (char c = 0; sent && head.find("\r\n\r\n") == std::string::npos && head.size() < 16384;) {
    if (!ReadExactly(fd, &c, 1)) break;
    head += c;
  }
  const std::string status_line = head.substr(0, head.find("\r\n"));
  if (status_line.find(" 101 ") == std::string::npos) {
    ::close(fd);
    return {Status::kUnavailable,
            uri + ": palpa serve refused the connection (" +
                (status_line.empty() ? std::string("no answer") : status_line) + ")"};
  }
  std::unique_ptr<ServeClient> client(new ServeClient(fd));
  client->reader_ = std::thread([c = client.get()] { c->Read(); });
  return client;
}

ServeClient::ServeClient(int fd) : fd_(fd) {}

ServeClient::~ServeClient() {
  Send(0x8, std::string("\x03\xe8", 2));  // close: normal
  ::shutdown(fd_, SHUT_RDWR);             // wakes the reader
  if (reader_.joinable()) reader_.join();
  ::close(fd_);
}

bool ServeClient::Send(uint8_t opcode, const std::string& payload) {
  std::string frame(1, static_cast<char>(0x80 | opcode));
  const size_t n = payload.size();
  if (n < 126) {
    frame += static_cast<char>(0x80 | n);
  } else if (n < 65536) {
    frame += static_cast<char>(0x80 | 126);
    frame += static_cast<char>(n >> 8);
    frame += static_cast<char>(n & 0xff);
  } else {
    frame += static_cast<char>(0x80 | 127);
    for (int shift = 56; shift >= 0; shift -= 8) frame += static_cast<char>((n >> shift) & 0xff);
  }
  const std::string mask = RandomBytes(4);
  frame += mask;
  for (size_t i = 0; i < n; ++i) frame += static_cast<char>(payload[i] ^ mask[i % 4]);
  std::lock_guard<std::mutex> lock(send_mutex_);
  return ::send(fd_, frame.data(), frame.size(), MSG_NOSIGNAL) ==
         static_cast<ssize_t>(frame.size());
}

void ServeClient::Read() {
  std::string message;
  for (;;) {
    uint8_t head[2];
    if (!ReadExactly(fd_, head, 2)) break;
    uint64_t n = head[1] & 0x7f;
    if (n >= 126) {
      uint8_t ext[8];
      const size_t bytes = n == 126 ? 2 : 8;
      if (!ReadExactly(fd_, ext, bytes)) break;
      n = 0;
      for (size_t i = 0; i < bytes; ++i) n = (n << 8) | ext[i];
    }
    if (n > (64u << 20)) break;  // beyond anything the server sends
    std::string payload(n, '\0');
    if (n > 0 && !ReadExactly(fd_, payload.data(), n)) break;
    const uint8_t opcode = head[0] & 0x0f;
    if (opcode == 0x9) {
      Send(0xA, payload);  // pong at once: three missed and the server counts us gone
      continue;
    }
    if (opcode == 0x8) break;
    if (opcode != 0x1 && opcode != 0x0) continue;
    message += payload;
    if (!(head[0] & 0x80)) continue;  // more fragments follow
    json m = json::parse(message, nullptr, false);
    message.clear();
    if (!m.is_object()) continue;
    std::lock_guard<std::mutex> lock(mutex_);
    if (m.contains("id")) {
      answers_.push_back(std::move(m));
    } else {
      if (notifications_.size() >= kMaxQueuedNotifications) notifications_.pop_front();
      notifications_.push_back(std::move(m));
    }
    arrived_.notify_all();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  arrived_.notify_all();
}

bool ServeClient::closed() {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

Result<json> ServeClient::Call(const std::string& method, const json& params, double timeout_s) {
  int64_t id = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    id = next_id_++;
  }
  const json request = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", params}};
  if (!Send(0x1, request.dump())) return {Status::kIoError, method + ": palpa serve went away"};
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    for (auto it = answers_.begin(); it != answers_.end(); ++it) {
      if ((*it)["id"] != id) continue;
      json answer = std::move(*it);
      answers_.erase(it);
      if (answer.contains("result")) return answer["result"];
      const json& e = answer.value("error", json::object());
      const json& data = e.value("data", json::object());
      Outcome o;
      const int code = e.value("code", 0);
      o.status =
          data.contains("status") && data["status"].is_string()
              ? StatusNamed(data["status"].get<std::string>())
              : (code == -32001 || code == -32002 ? Status::kBusy : Status::kInvalidArgument);
      o.message = e.value("message", std::string("refused"));
      return o;
    }
    if (closed_) return {Status::kIoError, method + ": palpa serve closed the connection"};
    if (arrived_.wait_until(lock, deadline) == std::cv_status::timeout)
      return {Status::kTimeout, method + ": no answer from palpa serve"};
  }
}

bool ServeClient::NextNotification(json& out, double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (notifications_.empty() && !closed_) {
    if (arrived_.wait_until(lock, deadline) == std::cv_status::timeout) break;
  }
  if (notifications_.empty()) return false;
  out = std::move(notifications_.front());
  notifications_.pop_front();
  return true;
}

}  // namespace palpa::host
