// The simulator's truth channel, read on a thread of its own.
#include "palpa/host/sim_truth.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace palpa::host {

bool TruthReader::Connect(const std::string& address) {
  // "tcp:IPV4:PORT", as palpa-sim prints it; anything else is refused, never guessed at.
  const size_t colon = address.rfind(':');
  if (address.compare(0, 4, "tcp:") != 0 || colon == std::string::npos || colon <= 4) return false;
  const std::string port = address.substr(colon + 1);
  if (port.empty() || port.size() > 5 ||
      port.find_first_not_of("0123456789") != std::string::npos || std::stoul(port) > 65535)
    return false;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(std::stoul(port)));
  if (inet_pton(AF_INET, address.substr(4, colon - 4).c_str(), &a.sin_addr) != 1) return false;
  fd_ = socket(AF_INET, SOCK_STREAM, 0);
  if (fd_ < 0 || connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) return false;
  thread_ = std::thread([this] { Run(); });
  return true;
}

TruthReader::~TruthReader() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) close(fd_);
}

std::vector<TruthReader::Sample> TruthReader::Since(double t_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Sample> out;
  for (const Sample& s : samples_) {
    if (s.t_s >= t_s) out.push_back(s);
  }
  return out;
}

bool TruthReader::Latest(Sample& out) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (samples_.empty()) return false;
  out = samples_.back();
  return true;
}

double TruthReader::now_s() {
  std::lock_guard<std::mutex> lock(mutex_);
  return samples_.empty() ? 0 : samples_.back().t_s;
}

void TruthReader::Run() {
  std::string pending;
  char buffer[8192];
  while (!stop_) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, 50) <= 0) continue;
    const ssize_t n = read(fd_, buffer, sizeof(buffer));
    if (n <= 0) return;
    pending.append(buffer, static_cast<size_t>(n));
    size_t newline;
    while ((newline = pending.find('\n')) != std::string::npos) {
      const auto j = nlohmann::json::parse(pending.substr(0, newline), nullptr, false);
      pending.erase(0, newline + 1);
      if (j.is_discarded()) continue;
      Sample s{j["board_time_us"].get<double>() / 1e6, {}};
      for (const auto& f : j["fingers"]) {
        s.outputs.push_back(f.contains("deformation_mm") ? f["deformation_mm"].get<double>()
                                                         : f["stiffness_n_per_mm"].get<double>());
      }
      std::lock_guard<std::mutex> lock(mutex_);
      samples_.push_back(s);
      if (keep_ > 0 && samples_.size() > keep_) samples_.pop_front();
    }
  }
}

}  // namespace palpa::host
