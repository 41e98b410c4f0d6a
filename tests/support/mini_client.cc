// A minimal protocol client for end-to-end tests: frames over TCP, a serial port or a BytePipe.
// port or a BytePipe, Hello, reliable commands and their answers.
#include "mini_client.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>

namespace palpa::testing {
namespace {

int64_t NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

MiniClient::~MiniClient() { Close(); }

void MiniClient::Close() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
  pipe_.reset();
}

bool MiniClient::ConnectTcp(const std::string& host, int port) {
  fd_ = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  inet_pton(AF_INET, host.c_str(), &addr.sin_addr);
  if (connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    Close();
    return false;
  }
  const int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return true;
}

bool MiniClient::OpenSerial(const std::string& path) {
  fd_ = open(path.c_str(), O_RDWR | O_NOCTTY);
  if (fd_ < 0) return false;
  termios raw{};
  tcgetattr(fd_, &raw);
  cfmakeraw(&raw);
  tcsetattr(fd_, TCSANOW, &raw);
  tcflush(fd_, TCIFLUSH);
  return true;
}

void MiniClient::SendBytes(const std::vector<uint8_t>& bytes) {
  last_sent_ms_ = NowMs();
  if (pipe_) {
    pipe_->Write(bytes.data(), bytes.size());
    return;
  }
  size_t at = 0;
  while (at < bytes.size()) {
    const ssize_t n = write(fd_, bytes.data() + at, bytes.size() - at);
    if (n <= 0) return;
    at += static_cast<size_t>(n);
  }
}

std::vector<ReceivedFrame> MiniClient::Read(int timeout_ms, bool (*until)(const ReceivedFrame&)) {
  std::vector<ReceivedFrame> frames;
  const int64_t deadline = NowMs() + timeout_ms;
  for (;;) {
    if (keepalive_ms_ > 0 && NowMs() - last_sent_ms_ >= keepalive_ms_)
      Send(pp::Heartbeat{session_, ++heartbeat_generation_});
    int64_t left = deadline - NowMs();
    if (left <= 0) break;
    if (keepalive_ms_ > 0) left = std::min<int64_t>(left, keepalive_ms_);
    uint8_t buffer[4096];
    ssize_t n = 0;
    if (pipe_) {
      n = pipe_->Read(buffer, sizeof(buffer), static_cast<int>(left));
      if (n < 0) break;
    } else {
      pollfd p{fd_, POLLIN, 0};
      const int ready = poll(&p, 1, static_cast<int>(left));
      if (ready < 0 || (ready == 0 && keepalive_ms_ == 0)) break;
      if (ready == 0) continue;  // time for the next heartbeat
      n = read(fd_, buffer, sizeof(buffer));
      if (n <= 0) break;
    }
    bool done = false;
    for (ssize_t i = 0; i < n; ++i) {
      if (decoder_.Process(buffer[i]) != pp::FrameDecoder::Event::kFrame) continue;
      const pp::Frame& f = decoder_.frame();
      frames.push_back(ReceivedFrame{f.header, std::vector<uint8_t>(f.body, f.body + f.body_size)});
      done |= until != nullptr && until(frames.back());
    }
    if (done) break;
  }
  return frames;
}

std::string MiniClient::ReadText(int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  if (poll(&p, 1, timeout_ms) <= 0) return {};
  char buffer[4096];
  const ssize_t n = read(fd_, buffer, sizeof(buffer));
  return n > 0 ? std::string(buffer, static_cast<size_t>(n)) : std::string();
}

pp::Result<pp::HelloReply> MiniClient::Hello(uint32_t nonce, int timeout_ms) {
  session_ = nonce;
  Send(pp::Hello{nonce, next_seq_});
  const int64_t deadline = NowMs() + timeout_ms;
  while (NowMs() < deadline) {
    for (const ReceivedFrame& f :
         Read(static_cast<int>(deadline - NowMs()),
              [](const ReceivedFrame& r) { return r.Is<pp::HelloReply>(); })) {
      if (f.Is<pp::HelloReply>() && f.As<pp::HelloReply>().host_nonce == nonce)
        return f.As<pp::HelloReply>();
      backlog.push_back(f);
    }
  }
  return pp::Status::kTimeout;
}

pp::Status MiniClient::RawSetpoint(uint8_t finger, uint8_t line, int32_t pa, uint32_t generation) {
  const pp::Status mode = Reliable(pp::SetFingerMode{finger, pp::FingerMode::kRaw});
  pp::SetLineSetpoints sp{};
  sp.generation = generation;
  sp.entry_count = 1;
  sp.entries[0] = {line, pa};
  Send(sp);
  return mode;
}

pp::Status MiniClient::WaitAnswer(uint8_t seq, uint8_t type, int timeout_ms) {
  const int64_t deadline = NowMs() + timeout_ms;
  while (NowMs() < deadline) {
    for (const ReceivedFrame& f : Read(
             static_cast<int>(deadline - NowMs()),
             [](const ReceivedFrame& r) { return (r.header.flags & pp::flags::kReliable) != 0; })) {
      backlog.push_back(f);
      if ((f.header.flags & pp::flags::kReliable) == 0 || f.header.seq != seq) continue;
      if (f.Is<pp::Ack>() && f.As<pp::Ack>().acked_type == type) return pp::Status::kOk;
      if (f.Is<pp::Nack>()) return f.As<pp::Nack>().status;
      return pp::Status::kOk;  // a report answers a query
    }
  }
  return pp::Status::kTimeout;
}

}  // namespace palpa::testing
