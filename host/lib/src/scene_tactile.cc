// Tactile arrays: groups checked and averaged, recorded streams and UDP frames read with every
// fault named, and the hold that lets the fingers go soft when the stream stops.
#include "palpa/host/scene_tactile.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>

#include "number_text.h"
#include "palpa/host/scene_files.h"

namespace palpa::host {

Outcome CheckTactile(const TactileSpec& s, size_t fingers) {
  const auto fail = [](const std::string& why) {
    return Outcome::Fail(Status::kInvalidArgument, "tactile." + why);
  };
  if (s.elements < 1 || s.elements > kMaxTactileElements)
    return fail("elements: " + std::to_string(s.elements) + " is outside 1 … " +
                std::to_string(kMaxTactileElements));
  if (s.groups.size() != fingers)
    return fail("groups: " + std::to_string(s.groups.size()) + " groups for the layout's " +
                std::to_string(fingers) + " fingers (one group a finger)");
  for (size_t g = 0; g < s.groups.size(); ++g) {
    const std::string at = "groups[" + std::to_string(g) + "]";
    if (s.groups[g].empty()) return fail(at + ": a group needs at least one element");
    for (size_t k = 0; k < s.groups[g].size(); ++k) {
      const size_t e = s.groups[g][k];
      if (e >= s.elements)
        return fail(at + "[" + std::to_string(k) + "]: element " + std::to_string(e) +
                    " is beyond the array's " + std::to_string(s.elements) + " (0 … " +
                    std::to_string(s.elements - 1) + ")");
      for (size_t j = 0; j < k; ++j) {
        if (s.groups[g][j] == e)
          return fail(at + "[" + std::to_string(k) + "]: element " + std::to_string(e) +
                      " is in the group already");
      }
    }
  }
  if (!(s.value_lo < s.value_hi) || !std::isfinite(s.value_lo) || !std::isfinite(s.value_hi))
    return fail("value_range: must rise (lo < hi), " + Num(s.value_lo) + " … " + Num(s.value_hi));
  if (!(s.hold_s >= 0 && s.hold_s <= kMaxTactileHoldS))
    return fail("hold_s: " + Num(s.hold_s) + " s is outside 0 … " + Num(kMaxTactileHoldS) + " s");
  return {};
}

std::vector<double> GroupMeans(const TactileSpec& s, const std::vector<double>& values) {
  std::vector<double> means;
  for (const auto& group : s.groups) {
    double sum = 0;
    for (size_t e : group) sum += e < values.size() ? values[e] : 0.0;
    means.push_back(sum / static_cast<double>(group.size()));
  }
  return means;
}

Result<std::vector<TactileFrame>> ParseTactileStream(const std::string& text,
                                                     const std::string& source, size_t elements) {
  using Frames = Result<std::vector<TactileFrame>>;
  const auto lines = CsvDataLines(text);
  const std::string head =
      source + ": line " + (lines.empty() ? "1" : std::to_string(lines[0].first));
  if (lines.empty() || lines[0].second.find("time_s") != lines[0].second.find_first_not_of(" \t"))
    return Frames(Status::kInvalidArgument,
                  head + ": expected the header time_s, then one name per element");
  size_t names = 1;
  for (char c : lines[0].second) names += c == ',';
  if (names != elements + 1)
    return Frames(Status::kInvalidArgument, head + ": " + std::to_string(names - 1) +
                                                " element columns, the scene's array has " +
                                                std::to_string(elements));
  if (lines.size() < 2) return Frames(Status::kInvalidArgument, source + ": no frames");
  std::vector<TactileFrame> frames;
  for (size_t k = 1; k < lines.size(); ++k) {
    const std::string where = source + ": line " + std::to_string(lines[k].first);
    auto v = ParseCsvNumbers(lines[k].second, where, elements + 1);
    if (!v.ok()) return v.outcome();
    if (v.value.size() != elements + 1)
      return Frames(Status::kInvalidArgument,
                    where + ": " + std::to_string(v.value.size()) + " values, expected " +
                        std::to_string(elements + 1) + " (the time and each element)");
    TactileFrame f;
    f.time_s = v.value[0];
    f.sequence = static_cast<uint32_t>(k - 1);
    if (!frames.empty() && !(f.time_s > frames.back().time_s))
      return Frames(Status::kInvalidArgument, where + ": time " + Num(f.time_s) +
                                                  " s is not after the line before's " +
                                                  Num(frames.back().time_s) + " s");
    f.values.assign(v.value.begin() + 1, v.value.end());
    frames.push_back(std::move(f));
  }
  return frames;
}

Result<std::vector<TactileFrame>> LoadTactileStream(const std::string& path, size_t elements) {
  const Result<std::string> text = ReadFileWhole(path, kTactileStreamLimits);
  if (!text.ok()) return text.outcome();
  return ParseTactileStream(text.value, path, elements);
}

namespace {
constexpr uint8_t kMagic[4] = {'P', 'T', 'A', '1'};

uint32_t Le32(const uint8_t* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}
}  // namespace

std::vector<uint8_t> EncodeTactilePacket(uint32_t sequence, const std::vector<double>& values) {
  std::vector<uint8_t> out(kMagic, kMagic + 4);
  const auto put32 = [&](uint32_t v) {
    for (int b = 0; b < 4; ++b) out.push_back(static_cast<uint8_t>(v >> (8 * b)));
  };
  put32(sequence);
  put32(static_cast<uint32_t>(values.size() & 0xFFFF));
  for (double v : values) {
    const float f = static_cast<float>(v);
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put32(bits);
  }
  return out;
}

Result<TactileFrame> DecodeTactilePacket(const uint8_t* data, size_t size, size_t elements) {
  using Frame = Result<TactileFrame>;
  if (size < kTactileHeaderBytes)
    return Frame(Status::kInvalidArgument,
                 std::to_string(size) + " bytes, shorter than the 12-byte header");
  if (std::memcmp(data, kMagic, 4) != 0)
    return Frame(Status::kInvalidArgument, "no PTA1 magic: not a palpa tactile frame");
  const uint32_t count_word = Le32(data + 8);
  const size_t count = count_word & 0xFFFF;
  if ((count_word >> 16) != 0)
    return Frame(Status::kInvalidArgument, "bytes 10 … 11 are reserved and must be zero");
  if (count != elements)
    return Frame(
        Status::kInvalidArgument,
        std::to_string(count) + " elements, the scene's array has " + std::to_string(elements));
  if (size != kTactileHeaderBytes + 4 * count)
    return Frame(Status::kInvalidArgument, std::to_string(size) + " bytes for " +
                                               std::to_string(count) + " elements, which take " +
                                               std::to_string(kTactileHeaderBytes + 4 * count));
  TactileFrame f;
  f.sequence = Le32(data + 4);
  for (size_t k = 0; k < count; ++k) {
    const uint32_t bits = Le32(data + kTactileHeaderBytes + 4 * k);
    float v;
    std::memcpy(&v, &bits, 4);
    if (!std::isfinite(v))
      return Frame(Status::kInvalidArgument, "element " + std::to_string(k) + " is not a number");
    f.values.push_back(v);
  }
  return f;
}

bool TactileHold::Receive(const TactileFrame& frame, double now_s) {
  if (held_) {
    const auto ahead = static_cast<int32_t>(frame.sequence - held_->sequence);
    if (ahead <= 0) {
      ++late_;
      return false;
    }
    missing_ += static_cast<size_t>(ahead - 1);
  }
  held_ = frame;
  arrived_s_ = now_s;
  return true;
}

const std::vector<double>* TactileHold::At(double now_s) const {
  if (!held_ || !(now_s - arrived_s_ <= hold_s_)) return nullptr;
  return &held_->values;
}

double MonotonicSeconds() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + t.tv_nsec * 1e-9;
}

Result<std::unique_ptr<TactileUdp>> TactileUdp::Open(const std::string& host, uint16_t port,
                                                     size_t elements) {
  using Opened = Result<std::unique_ptr<TactileUdp>>;
  const std::string where = "udp:" + (host.empty() ? "" : host + ":") + std::to_string(port);
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  if (const int rc =
          getaddrinfo(host.empty() ? nullptr : host.c_str(), service.c_str(), &hints, &found);
      rc != 0)
    return Opened(Status::kInvalidArgument, where + ": " + gai_strerror(rc));
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    freeaddrinfo(found);
    return Opened(Status::kIoError, where + ": " + std::strerror(errno));
  }
  const int bound = ::bind(fd, found->ai_addr, found->ai_addrlen);
  freeaddrinfo(found);
  if (bound != 0) {
    const int e = errno;
    ::close(fd);
    return Opened(Status::kIoError, where + ": cannot listen there: " + std::strerror(e));
  }
  sockaddr_in local{};
  socklen_t len = sizeof(local);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &len);
  return std::unique_ptr<TactileUdp>(new TactileUdp(fd, ntohs(local.sin_port), elements));
}

TactileUdp::~TactileUdp() { ::close(fd_); }

Result<std::optional<TactileFrame>> TactileUdp::Receive(int timeout_ms) {
  using Frame = Result<std::optional<TactileFrame>>;
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0 && errno != EINTR)
    return Frame(Status::kIoError, "udp:" + std::to_string(port_) + ": " + std::strerror(errno));
  if (ready <= 0) return Frame(std::nullopt);
  uint8_t buffer[kTactileHeaderBytes + 4 * kMaxTactileElements + 1];
  const ssize_t n = ::recv(fd_, buffer, sizeof(buffer), MSG_DONTWAIT | MSG_TRUNC);
  if (n < 0) return Frame(std::nullopt);
  const double now = MonotonicSeconds();
  auto frame =
      DecodeTactilePacket(buffer, std::min(static_cast<size_t>(n), sizeof(buffer)), elements_);
  if (!frame.ok()) {
    ++malformed_;
    last_problem_ = frame.message;
    return Frame(std::nullopt);
  }
  frame.value.time_s = now;
  return Frame(std::move(frame.value));
}

}  // namespace palpa::host
