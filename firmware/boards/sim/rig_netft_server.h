// palpa-sim's force sensor as an ATI Net F/T box: the RDT protocol over UDP. A request is 8
// bytes big-endian (0x1234, command, sample count): command 2 streams `count` records, 0 stops,
// 0x0042 sets the software bias (tare). A record is 36 bytes: RDT sequence, F/T sequence,
// status, then Fx Fy Fz Tx Ty Tz in counts (1 000 000 counts per N here), compression on +Fz.
// Unlike a real box, a stream is bounded: "0, until told to stop" and any larger count mean
// kMaxStreamRecords (one second of board time), so a forged request cannot turn the simulator
// into an endless reflector; a client that wants more asks again. The stream goes to the address
// of the start request only: a stop or bias from anyone else never redirects it.
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <string>

#include "palpa/hal/linux/opened.h"
#include "palpa/hal/sim/rig_model.h"

namespace palpa::sim {

class RigNetFtServer {
 public:
  static constexpr double kCountsPerNewton = 1000000;
  static constexpr uint32_t kMaxStreamRecords = 1000;
  ~RigNetFtServer();
  /// "udp:HOST:PORT" (0 = any free port). Refused naming --rig-netft: kBadValue for another form,
  /// kUnavailable when it cannot be bound.
  hal::Done Open(const std::string& spec, RigModel& rig);
  const std::string& address() const { return address_; }
  int fd() const { return fd_; }
  /// Answers the requests that have arrived (start, stop, bias).
  void Serve();
  /// Sends one record while streaming: call once per 1 ms board step.
  void Stream();

 private:
  void Send();
  RigModel* rig_ = nullptr;
  int fd_ = -1;
  std::string address_;
  sockaddr_in client_{};
  bool has_client_ = false;
  uint32_t remaining_ = 0;  ///< records still to stream to client_
  uint32_t rdt_sequence_ = 0, ft_sequence_ = 0;
  float bias_n_ = 0;
};

}  // namespace palpa::sim
