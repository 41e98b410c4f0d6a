// The chamber behind a line's outlet through a laminar tube, dC/dt = k (O − C)(O + C + 2 p_atm),
// as the board estimates it (the firmware's line step): the tube's constant from the lag a line
// is configured with, and back, and one step of the law. The calibration's fit, the display
// delay's prediction and the study's settle rule all take the chamber from here.
#pragma once

#include "palpa/protocol/messages_config.h"

namespace palpa::host {

/// The tube's constant k (1 / (Pa·s)) of a line of `kind` whose lag is `lag_s` at the board's
/// reference, the calibration step's mean pressure (core::ChamberStepMeanPa; what
/// ConfigureLine::chamber_tau_us holds): k = 1 / (2 lag (p_ref + p_atm)). 0 for no lag.
double TubeConstant(protocol::LineKind kind, double lag_s);

/// The lag at the board's reference of a tube of constant `k`: TubeConstant's inverse.
double TubeLag(protocol::LineKind kind, double k);

/// The chamber (Pa gauge) `dt_s` on, the outlet held at `outlet_pa` over it: exact for the rate
/// k (O + C + 2 p_atm) at this instant's pressures. k 0 (no tube): the outlet.
double TubeChamberAfter(double chamber_pa, double outlet_pa, double k, double dt_s);

}  // namespace palpa::host
