// Latched faults described for the person who must clear them.
#include "palpa/host/fault_text.h"

#include <cstdio>

#include "palpa/protocol/faults.h"

namespace palpa::host {

std::string FaultName(uint8_t fault) {
  // A newer board may latch a fault this host has no name for: shown, never dropped.
  return fault < static_cast<uint8_t>(protocol::Fault::kCount) ? protocol::kFaultNames[fault]
                                                               : "fault_" + std::to_string(fault);
}

std::string FaultNames(uint32_t bitmap) {
  std::string text;
  for (uint8_t f = 0; f < 32; ++f) {
    if ((bitmap & (1u << f)) != 0) text += (text.empty() ? "" : ", ") + FaultName(f);
  }
  return text.empty() ? "none" : text;
}

std::string FaultRemedy(uint8_t fault) {
  using protocol::Fault;
  switch (static_cast<Fault>(fault)) {
    case Fault::kHostSilence:
      return "the host commanding the board went silent while it was actuated (killed, hung or "
             "unplugged) — nothing to repair";
    case Fault::kOverLimit:
      return "a line read beyond its limits — check the supply pressure, the regulator and the "
             "sensor";
    case Fault::kImplausibleSensor:
      return "a sensor read no pressure, or one its regulator cannot have made — check its wiring "
             "and the chamber";
    case Fault::kConfigCrc:
      return "the live configuration changed in memory — load it again or factory-reset it";
    case Fault::kUnexpectedReset:
      return "the board restarted from a watchdog, brown-out or fault handler — check its supply "
             "and palpa diag";
    case Fault::kLeak:
      return "a chamber did not reach its setpoint in time — check tubing, seals and the supply";
    case Fault::kEStopCommand:
      return "an E-stop was commanded — make sure it is safe to go on";
    case Fault::kEStopPin:
      return "the E-stop input is asserted — release it first";
    case Fault::kPumpRunTime:
      return "the vacuum pump ran longer than allowed — check the vacuum circuit for leaks";
    case Fault::kOutputWrite:
      return "an output could not be written (a DAC channel, a valve or an enable; palpa diag says "
             "which) — check its driver and wiring";
    default:
      return "a fault this host has no description for (a newer board) — see palpa diag";
  }
}

std::string DescribeFaults(uint32_t bitmap, const protocol::Diagnostics* diagnostics) {
  std::string text;
  for (uint8_t f = 0; f < 32; ++f) {
    if ((bitmap & (1u << f)) == 0) continue;
    if (!text.empty()) text += "; ";
    text += FaultName(f);
    if (diagnostics != nullptr) {
      for (uint8_t i = diagnostics->history_count; i > 0; --i) {  // the latest latching
        const protocol::FaultRecord& r = diagnostics->history[i - 1];
        if (r.fault != f) continue;
        char when[64];
        std::snprintf(when, sizeof(when), ", latched at board time %.3f s",
                      static_cast<double>(r.time_us) / 1e6);
        text += when;
        break;
      }
    }
    text += ": " + FaultRemedy(f);
  }
  return text;
}

}  // namespace palpa::host
