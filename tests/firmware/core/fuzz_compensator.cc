// libFuzzer target: compensator parameters as the board receives them, then steps. Whatever
// validation accepts must build and step without undefined behaviour, and every drive must be
// finite and inside [0, the line's limit]; whatever it refuses must come with a reason.
// Input byte 0 picks the kind and how floats are read: raw bit patterns (NaN, infinities,
// denormals) or values spread over plausible decades, so accepted sets are common too.
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "palpa/core/compensator.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

namespace {

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool empty() const { return at_ >= size_; }
  uint8_t Byte() { return at_ < size_ ? data_[at_++] : 0; }
  float Raw() {
    uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits |= static_cast<uint32_t>(Byte()) << (8 * i);
    float v;
    std::memcpy(&v, &bits, sizeof(v));
    return v;
  }
  /// Sign, a decade from 1e-8 to 1e6 and a mantissa: every scale a parameter might take.
  float Spread() {
    const uint8_t sign_and_decade = Byte();
    const float mantissa = 1.0f + static_cast<float>(Byte()) / 32.0f;
    const float value = mantissa * std::pow(10.0f, static_cast<float>(sign_and_decade % 15) - 8);
    return (sign_and_decade & 0x80) != 0 ? -value : value;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t at_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
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
      f.params[i] = in.Raw();
    } else if (i % 3 == 2) {
      threshold += std::fabs(in.Spread()) * 1000.0f;
      f.params[i] = threshold;
    } else {
      f.params[i] = in.Spread();
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
  while (!in.empty()) {
    const float target = raw ? in.Raw() : std::fabs(in.Spread());
    if (!(target > 0) || !std::isfinite(target)) continue;  // the board maps 0 to 0 Pa itself
    const pc::CompensatorOutput out = pc::StepCompensator(c, s, target, applied);
    if (!std::isfinite(out.drive) || out.drive < 0 || out.drive > limit) std::abort();
    // The chamber: where the drive went, or a sensor reading anywhere in its range.
    applied = (in.Byte() & 1) != 0 ? out.drive : static_cast<float>(in.Byte()) * 500.0f;
  }
  return 0;
}
