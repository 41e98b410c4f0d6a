// palpa-sim's rig over Modbus: the simulated linear stage and force sensor served from the same
// plant and clock as the simulated board, so the calibration drivers are exercised for real.
// Register layout (unit 1; calibration/rigs/sim.json describes it to the drivers):
//   input   0-1  position, int32 µm (tip height above the vented surface), big word order
//   input   2    moving, 1 while the stage moves
//   holding 10-11 target, int32 µm
//   holding 12   speed, uint16 µm/s
//   holding 13   command: 1 move to target at speed, 2 stop (reads back 0 once taken)
//   holding 14   stop force, uint16 mN: a move commanded after it stops itself when the
//                controller's load-cell reading reaches it (0: none)
//   input   20-21 force, float32 N (compressive positive, after the tare)
//   holding 30   tare: write 1 to tare (reads back 0 once taken)
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "palpa/hal/linux/opened.h"
#include "palpa/hal/sim/rig_model.h"

typedef struct _modbus modbus_t;
typedef struct _modbus_mapping_t modbus_mapping_t;

namespace palpa::sim {

class RigModbusServer {
 public:
  /// TCP clients served at once (a calibration uses one or two); more are closed on arrival.
  static constexpr size_t kMaxClients = 4;
  ~RigModbusServer();
  /// "tcp:HOST:PORT" (0 = any free port) or "rtu:PATH" (a serial device or pty, 115200 8N1).
  /// Refused naming --rig-modbus: kBadValue for another form, kUnavailable when it cannot be
  /// listened on or opened.
  hal::Done Open(const std::string& spec, RigModel& rig);
  const std::string& address() const { return address_; }
  std::vector<int> PollFds() const;
  /// Accepts clients (up to kMaxClients), answers the requests waiting. Over TCP it never
  /// blocks: a request is answered once all its bytes have arrived, and a client sending faster
  /// than it is answered waits for the next pass; over RTU it waits at most for one request.
  void Pump();

 private:
  struct Client {
    int fd;
    std::vector<uint8_t> pending;  ///< TCP: bytes of a request not yet whole
  };
  void Refresh();
  void TakeWrites();
  void Answer(int fd, const uint8_t* request, int size);
  bool PumpTcp(Client& client);  ///< false when the client is gone or broke the framing
  void PumpRtu(int fd);

  RigModel* rig_ = nullptr;
  modbus_t* ctx_ = nullptr;
  modbus_mapping_t* map_ = nullptr;
  int listen_fd_ = -1;
  std::vector<Client> clients_;  ///< TCP: one per connected device driver; RTU: the serial line
  bool rtu_ = false;
  std::string address_;
};

}  // namespace palpa::sim
