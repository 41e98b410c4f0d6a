// Compensator cost image for the MPS2 AN386 (Cortex-M4F) under QEMU: every method and size steps
// through the same sweep of targets, each behind its own function so the instruction-count
// plugin can attribute steps to methods (tests/bench/hysteresis.sh). Exits through semihosting.
#include "palpa/core/compensator.h"
#include "palpa/core/curve.h"
#include "semihosting.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

namespace {

constexpr int kSteps = 2000;

/// Parameters of the right shape for each method (the cost does not depend on their values).
pp::ConfigureFinger Params(pp::CompensatorKind kind, int size) {
  pp::ConfigureFinger f{};
  f.compensator = kind;
  uint8_t n = 0;
  auto push = [&](float v) { f.params[n++] = v; };
  if (kind == pp::CompensatorKind::kBranch) {
    push(100.0f);
    push(500.0f);
    for (int i = 0; i < size; ++i)
      push(4000.0f * static_cast<float>(i) / static_cast<float>(size - 1));
    for (int i = 0; i < size; ++i)
      push(100000.0f * static_cast<float>(i) / static_cast<float>(size - 1));
    for (int i = 0; i < size; ++i)
      push(90000.0f * static_cast<float>(i) / static_cast<float>(size - 1));
  } else {
    if (kind == pp::CompensatorKind::kAsymmetricPi) push(static_cast<float>(size));
    push(-100.0f);
    push(0.02f);
    for (int i = 0; i < size; ++i)
      push(50000.0f * static_cast<float>(i) / static_cast<float>(size));
    for (int i = 0; i < size; ++i) push(0.002f);
    if (kind == pp::CompensatorKind::kAsymmetricPi) {
      for (float d : {500.0f, 1000.0f, 1500.0f, 2000.0f}) push(d);
      for (float g : {0.2f, -0.3f, 0.1f, -0.2f}) push(g);
    }
  }
  f.param_count = n;
  return f;
}

struct Run {
  pc::Compensator compensator;
  pc::CompensatorState state;
  float applied = 0;
};

/// The sweep: a triangle of targets over most of the range, each step fed the last drive. A
/// template on the step function, so every call is a direct one the plugin can see return.
template <float (*step)(Run&, float)>
__attribute__((noinline)) void Sweep(Run& r) {
  pc::HomeCompensator(r.compensator, r.state);
  for (int k = 0; k < kSteps; ++k) {
    const int phase = k % 400;
    const float target = 200.0f + 15.0f * static_cast<float>(phase < 200 ? phase : 400 - phase);
    r.applied = step(r, target);
  }
}

// One function per method and size: the plugin's spans are named after these.
#define PALPA_STEP(NAME)                                                         \
  __attribute__((noinline)) float NAME(Run& r, float target) {                   \
    return pc::StepCompensator(r.compensator, r.state, target, r.applied).drive; \
  }
PALPA_STEP(StepBranch4)
PALPA_STEP(StepBranch8)
PALPA_STEP(StepBranch12)
PALPA_STEP(StepBranch16)
PALPA_STEP(StepPi4)
PALPA_STEP(StepPi8)
PALPA_STEP(StepPi16)
PALPA_STEP(StepPi32)
PALPA_STEP(StepApi4)
PALPA_STEP(StepApi8)
PALPA_STEP(StepApi16)
PALPA_STEP(StepApi32)
#undef PALPA_STEP

const float kInverseOutput[] = {0, 500, 1000, 1500, 2000, 2500, 3000, 3500, 4000, 4370};
const float kInverseSetpoint[] = {0,     15500, 26400, 37300, 48300,
                                  59200, 70100, 81000, 91900, 100000};

__attribute__((noinline)) float StepNone(Run&, float target) {
  return pc::Interpolate(kInverseOutput, kInverseSetpoint, 10, target);
}

Run g_run;

}  // namespace

int main() {
  struct Case {
    pp::CompensatorKind kind;
    int size;
    void (*sweep)(Run&);
  };
  const Case cases[] = {{pp::CompensatorKind::kNone, 0, Sweep<StepNone>},
                        {pp::CompensatorKind::kBranch, 4, Sweep<StepBranch4>},
                        {pp::CompensatorKind::kBranch, 8, Sweep<StepBranch8>},
                        {pp::CompensatorKind::kBranch, 12, Sweep<StepBranch12>},
                        {pp::CompensatorKind::kBranch, 16, Sweep<StepBranch16>},
                        {pp::CompensatorKind::kPrandtlIshlinskii, 4, Sweep<StepPi4>},
                        {pp::CompensatorKind::kPrandtlIshlinskii, 8, Sweep<StepPi8>},
                        {pp::CompensatorKind::kPrandtlIshlinskii, 16, Sweep<StepPi16>},
                        {pp::CompensatorKind::kPrandtlIshlinskii, 32, Sweep<StepPi32>},
                        {pp::CompensatorKind::kAsymmetricPi, 4, Sweep<StepApi4>},
                        {pp::CompensatorKind::kAsymmetricPi, 8, Sweep<StepApi8>},
                        {pp::CompensatorKind::kAsymmetricPi, 16, Sweep<StepApi16>},
                        {pp::CompensatorKind::kAsymmetricPi, 32, Sweep<StepApi32>}};
  for (const Case& c : cases) {
    const pp::ConfigureFinger f = Params(c.kind, c.size);
    if (c.kind != pp::CompensatorKind::kNone && pc::CompensatorParamsError(f) != nullptr) {
      palpa::boards::mps2::SemihostExit(1);
    }
    g_run = Run{};
    g_run.compensator = pc::MakeCompensator(f, 100000.0f);
    c.sweep(g_run);
  }
  palpa::boards::mps2::SemihostExit(0);
}
