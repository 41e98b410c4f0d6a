// Status and fault bits in words, for people and for recordings: one place that names them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace palpa::host {

/// The line status bits set, by name ("slewing", "raw"); a bit this build has no name for (a
/// newer board) as "bit_N".
std::vector<std::string> LineStatusList(uint8_t status);
/// The latched faults, by name ("estop_command"); an unknown one as "fault_N".
std::vector<std::string> FaultList(uint32_t bitmap);
/// FaultList's inverse: the bits of the names given (what is not a fault's name is left out).
uint32_t FaultBitmap(const std::vector<std::string>& names);
/// Names joined by `separator`, or `none` when there are none ("slewing|raw", "ok").
std::string JoinNames(const std::vector<std::string>& names, const char* separator,
                      const char* none);

/// What a fault record's detail means for that fault, in words: "line 3", "120 ms of silence",
/// "reading 104000 Pa"; lines numbered from `number_from`. Empty where it carries nothing.
std::string FaultDetail(uint8_t fault, int32_t detail, int number_from);

}  // namespace palpa::host
