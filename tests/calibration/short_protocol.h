// The whole-protocol tests' settings: the quick protocol, dwelling 1 s, touching at 0.5 mm/s.
#pragma once

#include "palpa/calibration/calibration_protocol.h"

namespace palpa::testing {

inline calibration::ProtocolOptions ShortProtocol() {
  calibration::ProtocolOptions o = calibration::QuickProtocol();
  o.dwell_s = 1;
  o.contact.speed_mm_s = 0.5;
  return o;
}

}  // namespace palpa::testing
