// PI play-operator check on the Cortex-M4F under QEMU: the hand-scheduled ARMv7E-M pass against
// the C++ one for every operator count, random parameter sets, memories, drive changes (up to
// saturation) and starts (up to the ±2³⁰ clamp); and the PI step's saturating conversions (one
// VCVT, one SSAT) against their portable forms at the edges and at random. Exits through
// semihosting: 0 when every result and every memory word matched, 1 with the failing case
// printed.
#include <cstring>

#include "check_random.h"
#include "palpa/core/compensator.h"
#include "palpa/core/internal/compensator_tables.h"
#include "palpa/core/internal/float_ops.h"
#include "play_lanes.h"
#include "play_pairs.h"
#include "semihosting.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;
namespace mps2 = palpa::boards::mps2;

namespace {

palpa::boards::mps2::XorShift32 g_random(0x9E3779B9u);

uint32_t NextRandom() { return g_random.Next(); }

float Uniform(float lo, float hi) {
  return lo + (hi - lo) * static_cast<float>(NextRandom() >> 8) / 16777216.0f;
}

/// A valid pi parameter set of n operators: thresholds rising over 0..top, weights that may be
/// negative while every cumulative weight stays positive.
pp::ConfigureFinger RandomPi(uint8_t n) {
  pp::ConfigureFinger f{};
  f.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  f.param_count = static_cast<uint8_t>(2 + 2 * n);
  const float top = Uniform(100, 99000);
  const float w0 = Uniform(1e-4f, 0.05f);
  f.params[0] = Uniform(-50, 50);
  f.params[1] = w0;
  float cumulative = w0;
  for (uint8_t i = 0; i < n; ++i) {
    f.params[2 + i] = top * static_cast<float>(i) / static_cast<float>(n);
    float w = Uniform(-0.5f, 1.0f) * w0;
    if (cumulative + w <= 0.1f * w0) w = 0.5f * w0;
    cumulative += w;
    f.params[2 + n + i] = w;
  }
  return f;
}

int32_t RandomDriveChange() {
  switch (NextRandom() % 4) {
    case 0:
      return static_cast<int32_t>(NextRandom() % 65) - 32;
    case 1:
      return static_cast<int32_t>(NextRandom() % 4001) - 2000;
    case 2:
      return NextRandom() % 2 == 0 ? 32767 : -32768;
    default:
      return static_cast<int32_t>(NextRandom() % 65536) - 32768;
  }
}

int32_t RandomStart() {
  switch (NextRandom() % 3) {
    case 0:
      return static_cast<int32_t>(NextRandom() % (1u << 25)) - (1 << 24);
    case 1:
      return NextRandom() % 2 == 0 ? (1 << 30) : -(1 << 30);
    default:
      return static_cast<int32_t>(NextRandom() % (1u << 31)) - (1 << 30);
  }
}

/// The saturating conversions against their portable forms: 0 when all agree.
uint32_t CheckConversions() {
  const uint32_t edges[] = {0x00000000u, 0x80000000u, 0x3F000000u, 0xBF000000u, 0x3F7FFFFFu,
                            0xBF7FFFFFu, 0x4EFFFFFFu, 0x4F000000u, 0xCF000000u, 0xCF000001u,
                            0x7F800000u, 0xFF800000u, 0x7FC00000u, 0xFFC00000u, 0x7F7FFFFFu,
                            0x4E800000u, 0xCE800000u, 0x00000001u};
  uint32_t checked = 0;
  auto check = [&checked](uint32_t bits) {
    float v;
    std::memcpy(&v, &bits, sizeof(v));
    const int32_t i = pc::TruncateSaturating(v);
    ++checked;
    return i == pc::TruncateSaturatingPortable(v) &&
           pc::lanes::Saturate31(i) == pc::lanes::Saturate31Portable(i);
  };
  for (uint32_t bits : edges) {
    if (!check(bits)) return bits | 1u;
  }
  for (int k = 0; k < 20000; ++k) {
    const uint32_t bits = NextRandom();
    if (!check(bits)) return bits | 1u;
  }
  return checked > 20000 ? 0 : 1;
}

uint32_t g_fast[pc::kMaxPlayOperators / 2];
uint32_t g_reference[pc::kMaxPlayOperators / 2];

}  // namespace

int main() {
  if (const uint32_t bits = CheckConversions()) {
    mps2::SemihostPrintNumber("float bits", bits);
    mps2::SemihostPrint("play check: a saturating conversion differs from its portable form\n");
    mps2::SemihostExit(1);
  }
  uint32_t passes = 0;
  for (uint8_t n = 1; n <= pc::kMaxPlayOperators; ++n) {
    for (int set = 0; set < 8; ++set) {
      const pp::ConfigureFinger f = RandomPi(n);
      if (pc::CompensatorParamsError(f) != nullptr) {
        mps2::SemihostPrintNumber("operators", n);
        mps2::SemihostPrint("play check: generated an invalid parameter set\n");
        mps2::SemihostExit(1);
      }
      const pc::Compensator c = pc::MakeCompensator(f, 100000);
      pc::CompensatorState homed;
      pc::HomeCompensator(c, homed);
      const uint8_t pairs = static_cast<uint8_t>((n + 1) / 2);
      for (uint8_t k = 0; k < pairs; ++k) g_fast[k] = g_reference[k] = homed.play[k];
      for (int step = 0; step < 40; ++step) {
        if (step % 10 == 9) {  // now and then a memory no history could leave: same bits anyway
          for (uint8_t k = 0; k < pairs; ++k) g_fast[k] = g_reference[k] = NextRandom();
        }
        const int32_t moved = RandomDriveChange();
        const uint32_t shift = pc::lanes::Pack(moved, moved);
        const int32_t start = RandomStart();
        const int32_t fast =
            palpa_play_pairs_v7em(c.play.pair + pairs, g_fast + pairs, c.play.pair, shift, start);
        const int32_t reference =
            pc::PlayPairsPortable(c.play.pair, g_reference, pairs, shift, start);
        bool same = fast == reference;
        for (uint8_t k = 0; k < pairs; ++k) same = same && g_fast[k] == g_reference[k];
        ++passes;
        if (!same) {
          mps2::SemihostPrintNumber("operators", n);
          mps2::SemihostPrintNumber("set", static_cast<uint32_t>(set));
          mps2::SemihostPrintNumber("step", static_cast<uint32_t>(step));
          mps2::SemihostPrint("play check: mismatch\n");
          mps2::SemihostExit(1);
        }
      }
    }
  }
  mps2::SemihostPrintNumber("play check: passes equal", passes);
  mps2::SemihostPrint("\n");
  mps2::SemihostExit(0);
}
