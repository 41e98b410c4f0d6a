// ATI Net F/T force sensor (the Nano17's Ethernet box) over its RDT protocol on UDP: one sample
// per read, the software bias as the tare, the force axis and sign from the rig file.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "palpa/calibration/rig.h"

namespace palpa::calibration {

struct NetFtConfig {
  std::string uri;  ///< netft://HOST[:PORT] (port 49152 by default)
  std::string host;
  int port = 49152;
  double counts_per_force = 1000000;  ///< the box's "counts per force" (its calibration page)
  int axis = 2;                       ///< 0 Fx, 1 Fy, 2 Fz
  double sign = 1;                    ///< +1 when compression reads positive on that axis
  int timeout_ms = 200;
};

/// netft://HOST[:PORT]; an invalid argument saying what is wrong.
host::Result<NetFtConfig> ParseNetFtAddress(const std::string& uri);

class NetFtForceSensor final : public ForceSensor {
 public:
  /// Opens the UDP socket; not_found (an unknown host) or unavailable when it cannot.
  static host::Result<std::unique_ptr<NetFtForceSensor>> Open(const NetFtConfig& config);
  ~NetFtForceSensor() override;
  RigStatus Read(double* newtons) override;
  RigStatus Tare() override;

 private:
  NetFtForceSensor(const NetFtConfig& c, int fd) : config_(c), fd_(fd) {}
  RigStatus Request(uint16_t command, uint32_t count);
  NetFtConfig config_;
  int fd_;
};

}  // namespace palpa::calibration
