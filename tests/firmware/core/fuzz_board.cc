// libFuzzer target: the whole board behind its link, driven by a script of operations; what it
// checks after every loop pass, and the operations, are in board_script.h.
#include "board_script.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  palpa::testing::BoardScript(data, size).Run();
  return 0;
}
