// Line pipeline step by step: slew, feed-forward, PI trim (dead band, authority, anti-windup at
// each clamp), open-loop paths, the regulator minimum, the safe bypass and DAC scaling.
#include "palpa/core/line_pipeline.h"

#include "CppUTest/TestHarness.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;
namespace ls = pp::line_status;

namespace {

pp::ConfigureLine PressureLine() {
  pp::ConfigureLine c{};
  c.kind = pp::LineKind::kPressure;
  c.dac_bits = 12;
  c.dac_signal = pp::SignalRange::kVolt0To10;
  c.command_min_pa = 0;
  c.command_max_pa = 100000;
  c.limit_min_pa = 0;
  c.limit_max_pa = 100000;
  c.slew_pa_per_s = 0;
  c.regulator_min_pa = 1000;
  c.sensor = pp::SensorKind::kAnalog;
  c.trim_kp = 0.1f;
  c.trim_ki_per_s = 1.0f;
  c.trim_authority_pa = 5000;
  c.trim_dead_band_pa = 100;
  c.model_tau_us = 0;
  c.model_dead_time_us = 0;
  return c;
}

/// A line step's output with the DAC code it returned.
struct Stepped : pc::LineOutput {
  uint32_t counts = 0;
};

Stepped StepLine(const pc::LineParams& p, pc::LineState& s, float setpoint,
                 bool measured_valid = false, float measured = 0, bool safe = false) {
  Stepped out;
  const pc::LineReading reading{measured_valid, 0, measured};
  out.counts =
      safe ? pc::HoldLineSafe(p, s, reading, out) : pc::StepLine(p, s, setpoint, reading, out);
  return out;
}

}  // namespace

TEST_GROUP(LinePipeline){};

TEST(LinePipeline, SlewLimitsTheSetpointPerTick) {
  auto c = PressureLine();
  c.slew_pa_per_s = 100000;  // 100 Pa per 1 ms tick
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 0);
  auto out = StepLine(p, s, 50000);
  DOUBLES_EQUAL(100, s.slewed_pa, 1e-3);
  CHECK(out.status & ls::kSlewing);
  for (int i = 0; i < 499; ++i) StepLine(p, s, 50000);
  DOUBLES_EQUAL(50000, s.slewed_pa, 1e-2);
  out = StepLine(p, s, 50000);
  CHECK_FALSE(out.status & ls::kSlewing);
}

TEST(LinePipeline, FeedForwardInvertsTheRisingAndFallingCorrection) {
  auto c = PressureLine();
  c.sensor = pp::SensorKind::kNone;
  c.correction_count = 2;
  c.correction[0] = {0, 0, 1000};             // falling branch sits 1 kPa higher
  c.correction[1] = {100000, 98000, 100000};  // rising branch reaches only 98 kPa
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 0);
  auto out = StepLine(p, s, 49000);  // rising: the regulator makes 0.98 per commanded Pa
  DOUBLES_EQUAL(50000, out.command_pa, 1);
  CHECK(out.status & ls::kOpenLoop);
  out = StepLine(p, s, 40000);  // falling: produced = 1000 + 0.99 * command
  DOUBLES_EQUAL((40000 - 1000) / 0.99, out.command_pa, 1);
}

TEST(LinePipeline, BeyondTheCorrectionsPointsTheNearestEndsOffsetHolds) {
  // Measured over 10-90 kPa: the regulator makes 0.5 kPa less than commanded at the bottom and
  // 1 kPa less at the top.
  for (const bool vacuum : {false, true}) {
    auto c = PressureLine();
    c.sensor = pp::SensorKind::kNone;
    const int32_t sign = vacuum ? -1 : 1;
    if (vacuum) {
      c.kind = pp::LineKind::kVacuum;
      c.command_min_pa = 0;
      c.command_max_pa = c.limit_min_pa = -100000;
      c.limit_max_pa = 0;
    }
    c.correction_count = 2;
    c.correction[0] = {sign * 10000, sign * 9500, sign * 9500};
    c.correction[1] = {sign * 90000, sign * 89000, sign * 89000};
    const pc::LineParams p = pc::MakeLineParams(c, 1000);
    pc::LineState s;
    pc::ResetLineState(p, s, 0);
    DOUBLES_EQUAL(sign * 3500, StepLine(p, s, sign * 3000).command_pa,
                  1);  // not the 10 kPa point's
    DOUBLES_EQUAL(sign * 96000, StepLine(p, s, sign * 95000).command_pa, 1);
    DOUBLES_EQUAL(sign * (10000 + 40250 * 80000.0 / 79500), StepLine(p, s, sign * 49750).command_pa,
                  1);
  }
}

TEST(LinePipeline, WithoutCorrectionTheCommandIsTheSetpoint) {
  auto c = PressureLine();
  c.sensor = pp::SensorKind::kNone;
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 0);
  DOUBLES_EQUAL(30000, StepLine(p, s, 30000).command_pa, 1e-3);
}

TEST(LinePipeline, TrimIntegratesOutsideTheDeadBandOnly) {
  const pc::LineParams p = pc::MakeLineParams(PressureLine(), 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 20000);
  StepLine(p, s, 20000, true, 19950);  // 50 Pa error: inside ±100 Pa
  DOUBLES_EQUAL(0, s.integrator_pa, 1e-6);
  auto out = StepLine(p, s, 20000, true, 19000);  // 1 kPa short
  DOUBLES_EQUAL(1000 * 0.001, s.integrator_pa, 1e-4);
  DOUBLES_EQUAL(20000 + 0.1 * 1000 + 1.0, out.command_pa, 1e-2);
}

TEST(LinePipeline, TrimAuthorityClampsWithBackCalculation) {
  const pc::LineParams p = pc::MakeLineParams(PressureLine(), 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 50000);
  pc::LineOutput out;
  for (int i = 0; i < 5000; ++i) out = StepLine(p, s, 50000, true, 30000);  // 20 kPa short for 5 s
  CHECK(out.status & ls::kTrimClamped);
  DOUBLES_EQUAL(55000, out.command_pa, 1e-2);  // +5 % F.S. at most
  // Anti-windup: P + I equals the clamp, so the integrator did not run away to 100 kPa.
  DOUBLES_EQUAL(5000 - 0.1 * 20000, s.integrator_pa, 1e-2);
  out = StepLine(p, s, 50000, true, 50000);  // error gone: the trim drops at once
  CHECK(out.command_pa < 53100);
}

TEST(LinePipeline, FinalClampHoldsTheLimitsAndUnwindsTheIntegrator) {
  auto c = PressureLine();
  c.limit_max_pa = 60000;
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 60000);
  pc::LineOutput out;
  for (int i = 0; i < 3000; ++i) out = StepLine(p, s, 60000, true, 58000);
  DOUBLES_EQUAL(60000, out.command_pa, 1e-3);
  CHECK(out.status & ls::kSaturated);
  CHECK(s.integrator_pa <= 1e-3);  // back-calculated: nothing stored beyond the limit
}

TEST(LinePipeline, BelowTheRegulatorMinimumCommandsZeroWithTheIntegratorOff) {
  const pc::LineParams p = pc::MakeLineParams(PressureLine(), 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 20000);
  for (int i = 0; i < 100; ++i) StepLine(p, s, 20000, true, 15000);
  CHECK(s.integrator_pa > 0);
  const auto out = StepLine(p, s, 500, true, 15000);
  DOUBLES_EQUAL(0, out.command_pa, 0);
  DOUBLES_EQUAL(0, s.integrator_pa, 0);
  CHECK(out.status & ls::kOpenLoop);
  LONGS_EQUAL(0, out.counts);
}

TEST(LinePipeline, NoSensorOrInvalidReadingIsOpenLoop) {
  const pc::LineParams p = pc::MakeLineParams(PressureLine(), 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 0);
  const auto out = StepLine(p, s, 30000, false, 0);
  CHECK(out.status & ls::kOpenLoop);
  DOUBLES_EQUAL(30000, out.command_pa, 1e-3);
  DOUBLES_EQUAL(0, s.integrator_pa, 0);
}

TEST(LinePipeline, SafeBypassesSlewAndResetsTheState) {
  auto c = PressureLine();
  c.slew_pa_per_s = 1000;
  c.safe_pa = 0;
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 80000);
  const auto out = StepLine(p, s, 80000, true, 80000, true);
  DOUBLES_EQUAL(0, out.command_pa, 0);
  LONGS_EQUAL(0, out.counts);
  CHECK(out.status & ls::kSafe);
  DOUBLES_EQUAL(0, s.slewed_pa, 0);
}

TEST(LinePipeline, ReferenceModelHasTheRegulatorsDeadTimeAndLag) {
  auto c = PressureLine();
  c.model_tau_us = 20000;
  c.model_dead_time_us = 5000;
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  pc::LineState s;
  pc::ResetLineState(p, s, 0);
  for (int i = 0; i < 5; ++i) {
    StepLine(p, s, 10000);
    DOUBLES_EQUAL(0, s.reference_pa, 1e-3);  // nothing during the dead time
  }
  for (int i = 0; i < 20; ++i) StepLine(p, s, 10000);
  DOUBLES_EQUAL(10000 * (1 - 0.368), s.reference_pa, 300);  // one time constant later
}

TEST(LinePipeline, DacScalingForVoltageCurrentAndVacuum) {
  auto c = PressureLine();
  pc::LineParams p = pc::MakeLineParams(c, 1000);
  LONGS_EQUAL(0, pc::CountsFor(p, 0));
  LONGS_EQUAL(4095, pc::CountsFor(p, 100000));
  LONGS_EQUAL(2048, pc::CountsFor(p, 50000));
  LONGS_EQUAL(4095, pc::CountsFor(p, 250000));  // clamped to the DAC
  c.dac_signal = pp::SignalRange::kMilliamp4To20;
  p = pc::MakeLineParams(c, 1000);
  LONGS_EQUAL(819, pc::CountsFor(p, 0));  // 4 mA of a 0-20 mA DAC
  LONGS_EQUAL(4095, pc::CountsFor(p, 100000));
  pp::ConfigureLine v = PressureLine();
  v.kind = pp::LineKind::kVacuum;
  v.command_min_pa = 0;
  v.command_max_pa = -100000;
  v.limit_min_pa = -100000;
  v.limit_max_pa = 0;
  p = pc::MakeLineParams(v, 1000);
  LONGS_EQUAL(0, pc::CountsFor(p, 0));
  LONGS_EQUAL(4095, pc::CountsFor(p, -100000));
}

TEST(LinePipeline, LimitsAreIntersectedWithTheHardCeiling) {
  auto c = PressureLine();
  c.kind = pp::LineKind::kBias;
  c.limit_max_pa = 100000;  // a bias line can never exceed 20 kPa whatever it says
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  DOUBLES_EQUAL(20000, p.limit_max_pa, 0);
  pc::LineState s;
  pc::ResetLineState(p, s, 0);
  CHECK(StepLine(p, s, 90000).command_pa <= 20000);
}

TEST(LinePipeline, SensorSpanAndScaleArePreparedOncePerConfiguration) {
  auto c = PressureLine();
  c.sensor_min_pa = 0;
  c.sensor_max_pa = 103421;
  c.sensor_counts_min = 1638;
  c.sensor_counts_max = 14745;
  const pc::LineParams p = pc::MakeLineParams(c, 1000);
  const uint32_t margin = (14745 - 1638) / 50;  // 2 % of the span: 262 counts
  LONGS_EQUAL(1638 - margin, p.sensor_counts_low);
  LONGS_EQUAL(14745 + margin, p.sensor_counts_high);
  // The same arithmetic as the reading it replaced: min + (counts − counts_min) × span / counts.
  const float scale = 103421.0f / static_cast<float>(14745 - 1638);
  const float at_8000 = p.sensor_min_pa + (8000.0f - p.sensor_counts_min) * p.sensor_pa_per_count;
  DOUBLES_EQUAL(0.0f + (8000.0f - 1638.0f) * scale, at_8000, 0);
  // A margin larger than counts_min never wraps below zero.
  c.sensor_counts_min = 100;
  c.sensor_counts_max = 16000;
  LONGS_EQUAL(0, pc::MakeLineParams(c, 1000).sensor_counts_low);
}
