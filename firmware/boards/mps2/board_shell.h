// What the MPS2 board shell shares with its startup code.
#pragma once

#include <cstdint>

#include "../common/reset_record.h"

namespace palpa::boards::mps2 {

using boards::ResetRecord;

void WriteSafeCodes();  ///< every analogue output to its safe code, valves released
void OnSysTick();
void OnUartRx();

}  // namespace palpa::boards::mps2
