// The simulated rig's Modbus server (libmodbus), polled from palpa-sim's loop.
#include "rig_modbus_server.h"

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace palpa::sim {
namespace {

constexpr int kPosition = 0, kMoving = 2, kTarget = 10, kSpeed = 12, kCommand = 13, kStopForce = 14,
              kForce = 20, kTare = 30;

void PutI32(uint16_t* regs, int at, int32_t v) {
  const uint32_t u = static_cast<uint32_t>(v);
  regs[at] = static_cast<uint16_t>(u >> 16);
  regs[at + 1] = static_cast<uint16_t>(u);
}

int32_t GetI32(const uint16_t* regs, int at) {
  return static_cast<int32_t>(static_cast<uint32_t>(regs[at]) << 16 | regs[at + 1]);
}

bool Readable(int fd) {
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, 0) > 0 && (p.revents & (POLLIN | POLLHUP | POLLERR)) != 0;
}

}  // namespace

RigModbusServer::~RigModbusServer() {
  if (!rtu_) {
    for (const Client& c : clients_) close(c.fd);
  }
  if (listen_fd_ >= 0) close(listen_fd_);
  if (map_ != nullptr) modbus_mapping_free(map_);
  if (ctx_ != nullptr) {
    if (rtu_) modbus_close(ctx_);
    modbus_free(ctx_);
  }
}

hal::Done RigModbusServer::Open(const std::string& spec, RigModel& rig) {
  rig_ = &rig;
  map_ = modbus_mapping_new(0, 0, 40, 40);
  if (spec.rfind("tcp:", 0) == 0) {
    const std::string rest = spec.substr(4);
    const size_t colon = rest.rfind(':');
    if (colon == std::string::npos) {
      return {hal::Status::kBadValue, "--rig-modbus " + spec + ": expected tcp:HOST:PORT"};
    }
    const std::string host = rest.substr(0, colon);
    const int port = std::atoi(rest.substr(colon + 1).c_str());
    ctx_ = modbus_new_tcp(host.c_str(), port);
    listen_fd_ = ctx_ != nullptr ? modbus_tcp_listen(ctx_, 1) : -1;
    if (listen_fd_ < 0) {
      return {hal::Status::kUnavailable,
              "--rig-modbus " + spec + ": cannot listen (" + modbus_strerror(errno) + ")"};
    }
    sockaddr_in bound{};
    socklen_t size = sizeof(bound);
    getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &size);
    address_ = "tcp:" + host + ":" + std::to_string(ntohs(bound.sin_port));
  } else if (spec.rfind("rtu:", 0) == 0) {
    rtu_ = true;
    ctx_ = modbus_new_rtu(spec.substr(4).c_str(), 115200, 'N', 8, 1);
    if (ctx_ == nullptr || modbus_set_slave(ctx_, 1) != 0 || modbus_connect(ctx_) != 0) {
      return {hal::Status::kUnavailable,
              "--rig-modbus " + spec + ": cannot open (" + modbus_strerror(errno) + ")"};
    }
    clients_.push_back(Client{modbus_get_socket(ctx_), {}});
    address_ = spec;
  } else {
    return {hal::Status::kBadValue,
            "--rig-modbus " + spec + ": expected tcp:HOST:PORT or rtu:PATH"};
  }
  Refresh();
  return {};
}

std::vector<int> RigModbusServer::PollFds() const {
  std::vector<int> fds;
  for (const Client& c : clients_) fds.push_back(c.fd);
  if (listen_fd_ >= 0) fds.push_back(listen_fd_);
  return fds;
}

void RigModbusServer::Refresh() {
  PutI32(map_->tab_input_registers, kPosition,
         static_cast<int32_t>(std::lround(rig_->PositionMm() * 1000)));
  map_->tab_input_registers[kMoving] = rig_->stage().moving() ? 1 : 0;
  const float force = rig_->ReadForceN();
  uint32_t bits = 0;
  std::memcpy(&bits, &force, sizeof(bits));
  map_->tab_input_registers[kForce] = static_cast<uint16_t>(bits >> 16);
  map_->tab_input_registers[kForce + 1] = static_cast<uint16_t>(bits);
}

void RigModbusServer::TakeWrites() {
  uint16_t* h = map_->tab_registers;
  if (h[kCommand] == 1) {
    rig_->StopOnForce(static_cast<float>(h[kStopForce]) / 1000.0f);
    rig_->stage().MoveTo(static_cast<float>(GetI32(h, kTarget)) / 1000.0f,
                         static_cast<float>(h[kSpeed]) / 1000.0f);
  } else if (h[kCommand] == 2) {
    rig_->StopOnForce(0);
    rig_->stage().MoveTo(rig_->stage().position_mm(), 1.0f);
  }
  h[kCommand] = 0;
  if (h[kTare] == 1) rig_->Tare();
  h[kTare] = 0;
}

void RigModbusServer::Answer(int fd, const uint8_t* request, int size) {
  modbus_set_socket(ctx_, fd);
  Refresh();
  modbus_reply(ctx_, request, size, map_);
  TakeWrites();
}

bool RigModbusServer::PumpTcp(Client& c) {
  // A request is the MBAP header (transaction, protocol, length, unit) and the PDU: 6 bytes and
  // then `length` more. Read what has come, answer what is whole, keep the rest for later.
  uint8_t buffer[MODBUS_TCP_MAX_ADU_LENGTH];
  const size_t room = sizeof(buffer) - c.pending.size();
  const ssize_t n = recv(c.fd, buffer, room, MSG_DONTWAIT);
  if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) return false;
  if (n > 0) c.pending.insert(c.pending.end(), buffer, buffer + n);
  while (c.pending.size() >= 7) {
    const size_t length = static_cast<size_t>(c.pending[4]) << 8 | c.pending[5];
    if (length < 2 || 6 + length > MODBUS_TCP_MAX_ADU_LENGTH) return false;  // not Modbus TCP
    if (c.pending.size() < 6 + length) break;
    Answer(c.fd, c.pending.data(), static_cast<int>(6 + length));
    c.pending.erase(c.pending.begin(), c.pending.begin() + static_cast<long>(6 + length));
  }
  return true;
}

void RigModbusServer::PumpRtu(int fd) {
  while (Readable(fd)) {
    modbus_set_socket(ctx_, fd);
    uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH];
    const int n = modbus_receive(ctx_, query);
    if (n < 0) break;                 // noise on the line, or a request cut short
    if (n > 0) Answer(fd, query, n);  // 0: a request for another unit
  }
}

void RigModbusServer::Pump() {
  if (ctx_ == nullptr) return;
  if (rtu_) {
    PumpRtu(clients_.front().fd);
    return;
  }
  if (Readable(listen_fd_)) {
    const int fd = accept(listen_fd_, nullptr, nullptr);
    if (fd >= 0 && clients_.size() >= kMaxClients) {
      close(fd);  // full: closed at once rather than left waiting unanswered
    } else if (fd >= 0) {
      clients_.push_back(Client{fd, {}});
    }
  }
  for (size_t i = 0; i < clients_.size();) {
    if (PumpTcp(clients_[i])) {
      ++i;
    } else {
      close(clients_[i].fd);
      clients_.erase(clients_.begin() + static_cast<long>(i));
    }
  }
}

}  // namespace palpa::sim
