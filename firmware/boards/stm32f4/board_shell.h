// What the STM32F4 board shell shares with its startup code.
#pragma once

#include "../common/reset_record.h"

namespace palpa::boards::stm32f4 {

using boards::ResetRecord;

/// Every output safe in hardware: DAC CLR low (all outputs 0 V), valve and pump enables low.
/// Touches registers only, so it works from any fault handler.
void ForceOutputsSafe();

}  // namespace palpa::boards::stm32f4
