// RDT client for the ATI Net F/T.
#include "palpa/calibration/netft.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <regex>

namespace palpa::calibration {

host::Result<NetFtConfig> ParseNetFtAddress(const std::string& uri) {
  std::smatch m;
  if (!std::regex_match(uri, m, std::regex(R"(netft://([^:/]+)(:(\d{1,6}))?)")))
    return {Status::kInvalidArgument, "'" + uri + "' is not netft://HOST[:PORT]"};
  NetFtConfig c;
  c.uri = uri;
  c.host = m[1];
  if (m[3].matched) c.port = std::stoi(m[3]);
  if (c.port < 1 || c.port > 65535)
    return {Status::kInvalidArgument, "'" + uri + "': port 1..65535"};
  return c;
}

host::Result<std::unique_ptr<NetFtForceSensor>> NetFtForceSensor::Open(const NetFtConfig& config) {
  addrinfo hints{}, *found = nullptr;
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  if (getaddrinfo(config.host.c_str(), std::to_string(config.port).c_str(), &hints, &found) != 0 ||
      found == nullptr) {
    return {Status::kNotFound, config.uri + ": cannot resolve " + config.host};
  }
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  const bool ok = fd >= 0 && connect(fd, found->ai_addr, found->ai_addrlen) == 0;
  freeaddrinfo(found);
  if (!ok) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) close(fd);
    return {Status::kUnavailable, config.uri + ": " + why};
  }
  return std::unique_ptr<NetFtForceSensor>(new NetFtForceSensor(config, fd));
}

NetFtForceSensor::~NetFtForceSensor() {
  Request(0, 0);  // stop streaming
  close(fd_);
}

RigStatus NetFtForceSensor::Request(uint16_t command, uint32_t count) {
  const uint8_t r[8] = {0x12,
                        0x34,
                        static_cast<uint8_t>(command >> 8),
                        static_cast<uint8_t>(command),
                        static_cast<uint8_t>(count >> 24),
                        static_cast<uint8_t>(count >> 16),
                        static_cast<uint8_t>(count >> 8),
                        static_cast<uint8_t>(count)};
  if (send(fd_, r, sizeof(r), 0) != static_cast<ssize_t>(sizeof(r))) {
    return RigStatus::Fail(Status::kUnavailable, config_.uri + ": send: " + std::strerror(errno));
  }
  return {};
}

RigStatus NetFtForceSensor::Read(double* newtons) {
  // Drop whatever an earlier request left queued, then ask for one fresh record.
  uint8_t record[36];
  while (recv(fd_, record, sizeof(record), MSG_DONTWAIT) > 0) {
  }
  RigStatus s = Request(0x0002, 1);
  if (!s.ok()) return s;
  pollfd p{fd_, POLLIN, 0};
  if (poll(&p, 1, config_.timeout_ms) <= 0)
    return RigStatus::Fail(Status::kUnavailable, config_.uri + ": no record within " +
                                                     std::to_string(config_.timeout_ms) + " ms");
  const ssize_t n = recv(fd_, record, sizeof(record), 0);
  if (n != 36)
    return RigStatus::Fail(Status::kUnavailable, config_.uri + ": a record of " +
                                                     std::to_string(n) + " bytes, expected 36");
  const uint8_t* f = record + 12 + 4 * config_.axis;
  const int32_t counts =
      static_cast<int32_t>(static_cast<uint32_t>(f[0]) << 24 | f[1] << 16 | f[2] << 8 | f[3]);
  const uint32_t status =
      static_cast<uint32_t>(record[8]) << 24 | record[9] << 16 | record[10] << 8 | record[11];
  if (status != 0)
    return RigStatus::Fail(Status::kUnavailable,
                           config_.uri + ": the sensor reports status 0x" + std::to_string(status));
  *newtons = config_.sign * counts / config_.counts_per_force;
  return {};
}

RigStatus NetFtForceSensor::Tare() { return Request(0x0042, 0); }

}  // namespace palpa::calibration
