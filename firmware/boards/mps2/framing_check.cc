// Frame encoder check on the Cortex-M4F under QEMU: the ARMv7E-M word loop against CRC-then-COBS
// (the byte-wise encoders) for packets of every size, zero density and long zero-free runs.
// Exits through semihosting: 0 when every frame matched, 1 with the failing case printed.
#include "check_random.h"
#include "palpa/protocol/cobs.h"
#include "palpa/protocol/crc32.h"
#include "palpa/protocol/framing.h"
#include "semihosting.h"

namespace pp = palpa::protocol;

namespace {

palpa::boards::mps2::XorShift32 g_random(0x2545F491u);

uint32_t NextRandom() { return g_random.Next(); }

uint8_t g_packet[pp::kMaxPacketSize + pp::kCrcSize];
uint8_t g_copy[pp::kMaxPacketSize + pp::kCrcSize];
uint8_t g_fast[pp::kMaxFrameSize + 16];
uint8_t g_reference[pp::kMaxFrameSize];

// True when the fast path (spare room after the packet and in the output) equals the frame built
// from the CRC and the byte-wise COBS encoder.
bool FrameMatches(size_t size) {
  for (size_t i = 0; i < size; ++i) g_copy[i] = g_packet[i];
  const auto fast = pp::EncodeFrameInPlace(g_copy, size, g_fast, sizeof(g_fast));
  const uint32_t crc = pp::Crc32(g_packet, size);
  for (size_t i = 0; i < pp::kCrcSize; ++i)
    g_packet[size + i] = static_cast<uint8_t>(crc >> (8 * i));
  const size_t n = pp::CobsEncode(g_packet, size + pp::kCrcSize, g_reference, sizeof(g_reference));
  if (!fast.ok() || n == 0 || fast.value != n + 1 || g_fast[n] != 0) return false;
  for (size_t i = 0; i < n; ++i) {
    if (g_fast[i] != g_reference[i]) return false;
  }
  return true;
}

}  // namespace

int main() {
  uint32_t frames = 0;
  const uint32_t zero_percents[] = {0, 5, 30, 50, 90, 100};
  for (size_t size = pp::kHeaderSize; size <= pp::kMaxPacketSize; ++size) {
    for (uint32_t zero_percent : zero_percents) {
      for (size_t i = 0; i < size; ++i) {
        g_packet[i] =
            NextRandom() % 100 < zero_percent ? 0 : static_cast<uint8_t>(NextRandom() | 1u);
      }
      ++frames;
      if (!FrameMatches(size)) {
        palpa::boards::mps2::SemihostPrintNumber("size", static_cast<uint32_t>(size));
        palpa::boards::mps2::SemihostPrintNumber("zero%", zero_percent);
        palpa::boards::mps2::SemihostPrint("framing check: mismatch\n");
        palpa::boards::mps2::SemihostExit(1);
      }
    }
  }
  // Zero-free runs of 250..253 bytes at every offset in a word, with and without a zero after:
  // where the word loop hands a nearly full block to the byte-wise path.
  for (size_t run = 250; run <= pp::kMaxPacketSize - 3; ++run) {
    for (size_t start = 0; start < 4; ++start) {
      for (int zero_after = 0; zero_after < 2; ++zero_after) {
        size_t size = 0;
        for (; size < start; ++size) g_packet[size] = 0;
        for (size_t i = 0; i < run; ++i) g_packet[size++] = static_cast<uint8_t>(1 + i % 255);
        if (zero_after != 0 && size < pp::kMaxPacketSize) g_packet[size++] = 0;
        if (size < pp::kHeaderSize) continue;
        ++frames;
        if (!FrameMatches(size)) {
          palpa::boards::mps2::SemihostPrintNumber("run", static_cast<uint32_t>(run));
          palpa::boards::mps2::SemihostPrintNumber("start", static_cast<uint32_t>(start));
          palpa::boards::mps2::SemihostPrint("framing check: mismatch\n");
          palpa::boards::mps2::SemihostExit(1);
        }
      }
    }
  }
  palpa::boards::mps2::SemihostPrintNumber("framing check: frames equal", frames);
  palpa::boards::mps2::SemihostPrint("\n");
  palpa::boards::mps2::SemihostExit(0);
}
