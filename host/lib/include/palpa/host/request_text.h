// A finger request written as people write it — "L2", "0.5", "1.2mm", "0.9N/mm", "-10kPa" — read
// into a Request: one reading for the command line, the server and anything else that takes text.
#pragma once

#include <string>

#include "palpa/host/outcome.h"
#include "palpa/host/stiffness_map.h"

namespace palpa::host {

/// A decimal number ("5", "-10.5", "1e3"), finite: no hex, no "inf", no spaces.
bool ParseDecimal(const std::string& text, double& out);

/// "L2" (a level), "0.5" (0..1), "1.2mm", "0.9N/mm", "-10kPa". Units are spelled one way only:
/// "10kpa" is refused naming the unit meant. An invalid argument says what was wrong with the
/// value (without the value's owner: the caller names the finger).
Result<Request> ParseRequestText(const std::string& value);

/// A line pressure in kPa: "30" or "-40kPa". "-40kpa" is refused naming the unit meant.
Result<double> ParsePressureText(const std::string& value);

}  // namespace palpa::host
