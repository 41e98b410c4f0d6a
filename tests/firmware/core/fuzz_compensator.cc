// libFuzzer target: compensator parameters as the board receives them, then steps. Whatever
// validation accepts must build and step without undefined behaviour, and every drive must be
// finite and inside [0, the line's limit]; whatever it refuses must come with a reason.
// Input byte 0 picks the kind and how floats are read: raw bit patterns (NaN, infinities,
// denormals) or values spread over plausible decades, so accepted sets are common too.
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "fuzz_input.h"
#include "palpa/core/compensator.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

namespace {

/// Sign, a decade from 1e-8 to 1e6 and a mantissa: every scale a parameter might take.
float Spread(palpa::testing::FuzzInput& in) {
  const uint8_t sign_and_decade = in.Byte();
  const float mantissa = 1.0f + static_cast<float>(in.Byte()) / 32.0f;
  const float value = mantissa * std::pow(10.0f, static_cast<float>(sign_and_decade % 15) - 8);
  return (sign_and_decade & 0x80) != 0 ? -value : value;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  palpa::testing::FuzzInput in(data, size);
  const uint8_t mode = in.Byte();
  const pp::CompensatorKind kinds[] = {pp::CompensatorKind::kNone, pp::CompensatorKind::kBranch,
                                       pp::CompensatorKind::kPrandtlIshlinskii,
                                       pp::CompensatorKind::kAsymmetricPi};
  pp::ConfigureFinger f{};
  f.compensator = kinds[mode % 4];
  const bool raw = (mode & 0x04) != 0;
  f.param_count = static_cast<uint8_t>(in.Byte() % (f.params.size() + 1));
  float threshold = 0;
  for (uint8_t i = 0; i < f.param_count; ++i) {
    // In spread mode every third value climbs, so increasing thresholds and curves occur often.
    if (raw) {
      f.params[i] = in.FloatBits();
    } else if (i % 3 == 2) {
      threshold += std::fabs(Spread(in)) * 1000.0f;
      f.params[i] = threshold;
    } else {
      f.params[i] = Spread(in);
    }
  }
  if (f.compensator == pp::CompensatorKind::kAsymmetricPi && f.param_count > 0 && !raw) {
    f.params[0] = static_cast<float>(1 + in.Byte() % 32);  // an operator count it can accept
  }
  const char* why = pc::CompensatorParamsError(f);
  if (why != nullptr) {
    if (std::strlen(why) < 10) std::abort();  // a refusal says what is wrong
    return 0;
  }
  const float limit = 1000.0f + 1000.0f * static_cast<float>(in.Byte() % 100);
  const pc::Compensator c = pc::MakeCompensator(f, limit);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  float applied = 0;
  while (!in.done()) {
    const float target = raw ? in.FloatBits() : std::fabs(Spread(in));
    if (!(target > 0) || !std::isfinite(target)) continue;  // the board maps 0 to 0 Pa itself
    const pc::CompensatorOutput out = pc::StepCompensator(c, s, target, applied);
    if (!std::isfinite(out.drive) || out.drive < 0 || out.drive > limit) std::abort();
    // The chamber: where the drive went, or a sensor reading anywhere in its range.
    applied = (in.Byte() & 1) != 0 ? out.drive : static_cast<float>(in.Byte()) * 500.0f;
  }
  return 0;
}
