// Shared by calibration's sources: a number in a message, a look at a moving rig.
// watched.
#pragma once

#include <string>

#include "palpa/calibration/rig.h"

namespace palpa::calibration {

/// A number in a message: `digits` significant figures ("%.*g").
std::string Num(double v, int digits = 3);

/// One look at the rig while something moves: force, position, board faults. Fails naming the
/// limit crossed or the device lost.
RigStatus Watch(Rig& rig, double* force, double* position);

}  // namespace palpa::calibration
