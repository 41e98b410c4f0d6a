// ARM semihosting calls for the self-test images under QEMU: print, and exit with a status.
#pragma once

#include <cstdint>

namespace palpa::boards::mps2 {

inline int32_t Semihost(uint32_t operation, const void* argument) {
  register uint32_t r0 asm("r0") = operation;
  register const void* r1 asm("r1") = argument;
  asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return static_cast<int32_t>(r0);
}

inline void SemihostPrint(const char* text) { Semihost(0x04, text); }  // SYS_WRITE0

/// Prints "label value " (the check images' failure reports and counts).
inline void SemihostPrintNumber(const char* label, uint32_t value) {
  SemihostPrint(label);
  char text[12];
  int n = 11;
  text[n] = '\0';
  text[--n] = ' ';
  do {
    text[--n] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  text[--n] = ' ';
  SemihostPrint(text + n);
}

[[noreturn]] inline void SemihostExit(uint32_t code) {
  const uint32_t block[2] = {0x20026u, code};  // ADP_Stopped_ApplicationExit
  Semihost(0x20, block);                       // SYS_EXIT_EXTENDED
  for (;;) {
  }
}

}  // namespace palpa::boards::mps2
