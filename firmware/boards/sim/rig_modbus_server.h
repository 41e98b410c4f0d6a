// palpa-sim's rig over Modbus: the simulated linear stage and force sensor served from the same
// plant and clock as the simulated board, so the calibration drivers are exercised for real.
// Register layout (unit 1; calibration/rigs/sim.json describes it to the drivers):
//   input   0-1  position, int32 µm (tip height above the vented surface), big word order
//   input   2    moving, 1 while the stage moves
//   holding 10-11 target, int32 µm
//   holding 12   speed, uint16 µm/s
//   holding 13   command: 1 move to target at speed, 2 stop (reads back 0 once taken)
//   input   20-21 force, float32 N (compressive positive, after the tare)
//   holding 30   tare: write 1 to tare (reads back 0 once taken)
#pragma once

#include <string>
#include <vector>

#include "palpa/hal/sim/rig_model.h"

typedef struct _modbus modbus_t;
typedef struct _modbus_mapping_t modbus_mapping_t;

namespace palpa::sim {

class RigModbusServer {
 public:
  ~RigModbusServer();
  /// "tcp:HOST:PORT" (0 = any free port) or "rtu:PATH" (a serial device or pty, 115200 8N1).
  bool Open(const std::string& spec, RigModel& rig, std::string* error);
  const std::string& address() const { return address_; }
  std::vector<int> PollFds() const;
  /// Accepts clients, answers any request waiting. Never blocks for longer than one request.
  void Pump();

 private:
  void Refresh();
  void TakeWrites();

  RigModel* rig_ = nullptr;
  modbus_t* ctx_ = nullptr;
  modbus_mapping_t* map_ = nullptr;
  int listen_fd_ = -1;
  std::vector<int> clients_;  ///< TCP: one per connected device driver; RTU: the serial line
  bool rtu_ = false;
  std::string address_;
};

}  // namespace palpa::sim
