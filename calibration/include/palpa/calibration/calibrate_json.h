// One finger calibrated as palpa calibrate calibrates it, its options given as JSON: the call
// the C ABI (palpa_calibrate) and Python (Device.calibrate, palpa.calibrate_simulated) make.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "palpa/calibration/session.h"
#include "palpa/host/device.h"

namespace palpa::calibration {

/// The options, every key optional but "finger" and "out" (fingers numbered from 0):
///   {"finger": 0, "out": "DIR", "quick": false, "protocol": "thesis" | "adaptive",
///    "compensator": "auto" | "pi" | "api", "operators": 0 (the default) to 32,
///    "target_pct": 2.5, "max_cycles": 18, "allow_fallback": false, "resume": false,
///    "previous": "FILE", "apply": false,
///    "sim": {"config": "thesis-5finger", "speed": 4, "unit": 0, "seed": 1, "plant": 3,
///            "effects": ""}}
/// `rig` is a rig file, calibrated beside `device`, or "sim": palpa-sim started for the run with
/// "sim"'s options (then `device` is not used and may be null). The files go to "out" as palpa
/// calibrate writes them; "apply" uploads the result to the finger. On success *summary is what
/// palpa calibrate --json prints (Session::Summary). kInvalidArgument names a bad option; other
/// failures are the Session's phases'.
host::Outcome CalibrateFromJson(host::Device* device, const std::string& rig,
                                const nlohmann::json& options, nlohmann::ordered_json* summary);

}  // namespace palpa::calibration
