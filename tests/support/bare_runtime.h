// The C library functions a compiler may lower loops to, and the entry point, for test programs
// linked with no runtime at all (the freestanding link checks). A bare-metal image provides them
// the same way. Define-once: include in exactly one translation unit of a program, which defines
// palpa_check_main(): the program's exit code.
#pragma once

extern "C" {
void* memcpy(void* dst, const void* src, __SIZE_TYPE__ n) {
  auto* d = static_cast<unsigned char*>(dst);
  const auto* s = static_cast<const unsigned char*>(src);
  while (n--) *d++ = *s++;
  return dst;
}
void* memmove(void* dst, const void* src, __SIZE_TYPE__ n) {
  auto* d = static_cast<unsigned char*>(dst);
  const auto* s = static_cast<const unsigned char*>(src);
  if (d < s) {
    while (n--) *d++ = *s++;
  } else {
    while (n--) d[n] = s[n];
  }
  return dst;
}
void* memset(void* dst, int value, __SIZE_TYPE__ n) {
  auto* d = static_cast<unsigned char*>(dst);
  while (n--) *d++ = static_cast<unsigned char>(value);
  return dst;
}
int memcmp(const void* a, const void* b, __SIZE_TYPE__ n) {
  const auto* x = static_cast<const unsigned char*>(a);
  const auto* y = static_cast<const unsigned char*>(b);
  for (; n; --n, ++x, ++y) {
    if (*x != *y) return *x - *y;
  }
  return 0;
}
}

extern "C" int palpa_check_main();

// Entry point without a C runtime: align the stack as a call would, run, exit(code) (Linux x86-64).
asm(R"(
  .globl _start
_start:
  xor %ebp, %ebp
  and $-16, %rsp
  call palpa_check_main
  mov %eax, %edi
  mov $60, %eax
  syscall
)");
