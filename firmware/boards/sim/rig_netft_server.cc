// The simulated Net F/T (RDT over UDP).
#include "rig_netft_server.h"

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstring>

namespace palpa::sim {
namespace {

void Put32(uint8_t* p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v >> 24);
  p[1] = static_cast<uint8_t>(v >> 16);
  p[2] = static_cast<uint8_t>(v >> 8);
  p[3] = static_cast<uint8_t>(v);
}

}  // namespace

RigNetFtServer::~RigNetFtServer() {
  if (fd_ >= 0) close(fd_);
}

hal::Done RigNetFtServer::Open(const std::string& spec, RigModel& rig) {
  rig_ = &rig;
  const size_t colon = spec.rfind(':');
  if (spec.rfind("udp:", 0) != 0 || colon <= 4) {
    return {hal::Status::kBadValue, "--rig-netft " + spec + ": expected udp:HOST:PORT"};
  }
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(std::atoi(spec.substr(colon + 1).c_str())));
  if (inet_pton(AF_INET, spec.substr(4, colon - 4).c_str(), &a.sin_addr) != 1) {
    return {hal::Status::kBadValue, "--rig-netft " + spec + ": not an IPv4 address"};
  }
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    return {hal::Status::kUnavailable,
            "--rig-netft " + spec + ": cannot bind (" + std::strerror(errno) + ")"};
  }
  socklen_t size = sizeof(a);
  getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &size);
  address_ = "udp:" + spec.substr(4, colon - 4) + ":" + std::to_string(ntohs(a.sin_port));
  return {};
}

void RigNetFtServer::Send() {
  uint8_t record[36] = {};
  Put32(record, ++rdt_sequence_);
  Put32(record + 4, ++ft_sequence_);
  Put32(record + 8, 0);  // status: healthy
  const double fz = rig_->ReadForceN() - bias_n_;
  Put32(record + 20,
        static_cast<uint32_t>(static_cast<int32_t>(std::lround(fz * kCountsPerNewton))));  // Fz
  sendto(fd_, record, sizeof(record), 0, reinterpret_cast<const sockaddr*>(&client_),
         sizeof(client_));
}

void RigNetFtServer::Serve() {
  if (fd_ < 0) return;
  uint8_t request[8];
  sockaddr_in from{};
  socklen_t size = sizeof(from);
  ssize_t n;
  while ((n = recvfrom(fd_, request, sizeof(request), 0, reinterpret_cast<sockaddr*>(&from),
                       &size)) == 8) {
    if (request[0] != 0x12 || request[1] != 0x34) continue;  // not an RDT request
    const uint16_t command = static_cast<uint16_t>(request[2] << 8 | request[3]);
    const uint32_t count =
        static_cast<uint32_t>(request[4]) << 24 | request[5] << 16 | request[6] << 8 | request[7];
    const bool from_client = has_client_ && from.sin_addr.s_addr == client_.sin_addr.s_addr &&
                             from.sin_port == client_.sin_port;
    if (command == 0x0042) {
      bias_n_ = rig_->ReadForceN();
    } else if (command == 0) {
      if (from_client) remaining_ = 0;  // only who asked for the stream can stop it
    } else {
      client_ = from;  // the stream goes to who asked for it, and to nobody else
      has_client_ = true;
      remaining_ = count == 0 || count > kMaxStreamRecords ? kMaxStreamRecords : count;
    }
  }
}

void RigNetFtServer::Stream() {
  if (has_client_ && remaining_ > 0) {
    Send();
    --remaining_;
  }
}

}  // namespace palpa::sim
