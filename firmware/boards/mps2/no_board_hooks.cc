// The board shell's hooks for images that run one computation and exit (compensator bench,
// framing check): no outputs to make safe, no tick, no link.
#include "board_shell.h"

namespace palpa::boards::mps2 {
void WriteSafeCodes() {}
void OnSysTick() {}
void OnUartRx() {}
}  // namespace palpa::boards::mps2
