// Prediction: the display's half-step delay from a line's calibrated model, and the hand's
// motion extrapolated over it — exact on an even motion, capped, held on the tissue, and not at
// all on reversals, stops, noise, gaps or a lifted pen.
#include <cmath>
#include <random>

#include "palpa/host/scene_predict.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

ph::PredictorOptions Options(double horizon_s) {
  ph::PredictorOptions o;
  o.horizon_s = horizon_s;
  return o;
}

/// Samples at 100 Hz along x at `speed` from x0, y = 15, 1 N.
ph::SceneInput At(int k, double speed, double x0 = 20) {
  return {k * 0.01, x0 + speed * k * 0.01, 15, 1};
}

}  // namespace

SimpleString StringFrom(ph::Prediction p) { return ph::PredictionName(p); }

TEST_GROUP(ScenePredict){};

TEST(ScenePredict, HalfStepTimes) {
  // Unshaped: dead time then one lag crosses half at dead + τ ln 2 (the model's tenth-of-a-tick
  // steps: within a few of them).
  DOUBLES_EQUAL(0.005 + 0.02 * std::log(2.0), ph::HalfStepTime({0.005, 0.02, 0, 0}, 30000), 3e-4);
  DOUBLES_EQUAL(0.005, ph::HalfStepTime({0.005, 0, 0, 0}, 30000), 2e-4);
  // Two equal lags cross half at 1.67835 τ. The chamber's is the tube's: 20 ms at the
  // calibration step's mean pressure (30 kPa), 1.296 × that at atmosphere (the absolute
  // pressures' sum 2 × 101.3 kPa against 2 × 131.3 kPa), so a step 0 → 30 kPa takes longer than
  // two lags of 20 ms and less than a chamber lag of 26 ms throughout would.
  const double rising = ph::HalfStepTime({0, 0.02, 0.02, 0}, 30000);
  CHECK(rising > 1.67835 * 0.02 + 3e-4);
  CHECK(rising < 1.67835 * 0.02 * 1.296);
  // A vacuum line's chamber, the same lag identified (at 12.5 kPa of vacuum), is slower the
  // deeper it goes: a step to −80 kPa takes longer than one to +80 kPa (one lag: the same).
  ph::LineDynamics vacuum{0, 0.02, 0.02, 0, true, 0};
  CHECK(ph::HalfStepTime(vacuum, 80000) > 1.2 * ph::HalfStepTime({0, 0.02, 0.02, 0}, 80000));
  // Shaped with room to overdrive (the board's lead on the chamber model): far faster than the
  // chamber's lag alone would allow, never faster than dead time and the regulator's lag.
  const ph::LineDynamics shaped{0.005, 0.02, 0.05, 1e9};
  CHECK(ph::HalfStepTime(shaped, 30000) > 0.005 + 0.02 * std::log(2.0));
  CHECK(ph::HalfStepTime(shaped, 30000) < 0.005 + 0.05 * std::log(2.0));
  // Held within a 20 kPa overdrive: a 30 kPa step is partly shaped. A 100 kPa step goes to the
  // line's limit, beyond which the board never commands: no overdrive at all, the unshaped step.
  const ph::LineDynamics bounded{0.005, 0.02, 0.05, 20000};
  const double unshaped = ph::HalfStepTime({0.005, 0.02, 0.05, 0}, 30000);
  const double unshaped_large = ph::HalfStepTime({0.005, 0.02, 0.05, 0}, 100000);
  const double small = ph::HalfStepTime(bounded, 30000), large = ph::HalfStepTime(bounded, 100000);
  CHECK(small > ph::HalfStepTime(shaped, 30000) + 1e-3);
  CHECK(small < unshaped);
  DOUBLES_EQUAL(unshaped_large, large, 1e-9);
  CHECK(unshaped_large < unshaped);  // the tube is faster at the larger step's higher pressure
  // A chamber faster than the regulator: no lead, but the board still drives the regulator
  // model through its lag (the command beyond the target, within the overdrive), so the step
  // is quicker than dead time and the regulator's lag alone.
  const ph::LineDynamics quick{0.005, 0.02, 0.0025, 20000};
  CHECK(ph::HalfStepTime(quick, 30000) < 0.005 + 0.02 * std::log(2.0) - 2e-3);
  CHECK(ph::HalfStepTime(quick, 30000) > 0.005);
}

TEST(ScenePredict, DisplayDelayFromTheCalibratedLine) {
  pp::ConfigureLine line;
  line.line = 2;
  line.model_dead_time_us = 5000;
  line.model_tau_us = 20000;
  line.limit_max_pa = line.command_max_pa = line.sensor_max_pa = 100000;
  line.sensor = pp::SensorKind::kAnalog;
  line.sensor_counts_max = 16383;
  const auto unknown = ph::DisplayDelay(line, 30000);
  CHECK(!unknown.ok());
  STRCMP_CONTAINS("line 3 has no chamber model", unknown.message.c_str());
  line.chamber_tau_us = 50000;
  const auto unshaped = ph::DisplayDelay(line, 30000);
  CHECK(unshaped.ok());
  DOUBLES_EQUAL(ph::HalfStepTime({0.005, 0.02, 0.05, 0}, 30000), unshaped.value, 1e-12);
  line.overdrive_pa = 20000;  // shaped steps: the chamber driven through its lag, within 20 kPa
  DOUBLES_EQUAL(ph::HalfStepTime({0.005, 0.02, 0.05, 20000}, 30000),
                ph::DisplayDelay(line, 30000).value, 1e-12);
  CHECK(ph::DisplayDelay(line, 30000).value < unshaped.value);
  // The board shapes nothing on a line without a sensor (it estimates the chamber from the
  // outlet's reading), nor beyond the slew limit the line is configured with.
  line.sensor = pp::SensorKind::kNone;
  DOUBLES_EQUAL(unshaped.value, ph::DisplayDelay(line, 30000).value, 1e-12);
  line.sensor = pp::SensorKind::kAnalog;
  line.slew_pa_per_s = 200000;  // 150 ms to 30 kPa
  CHECK(ph::DisplayDelay(line, 30000).value > 0.075);
}

TEST(ScenePredict, DrivesFoundOnTheFingersCurves) {
  const ph::FingerCurves nominal;
  // Table 5-4's line: 0.0458 mm/kPa − 0.2098 mm; 1 mm at 26.4 kPa.
  DOUBLES_EQUAL((1 + 0.2098) / 0.0458, ph::DriveForOutput(pp::FingerKind::kPneumatic, nominal, 1),
                1e-6);
  // Jamming, nominal 0.7 … 1.3 N/mm over 0 … −100 kPa: 1.0 N/mm at −50 kPa.
  DOUBLES_EQUAL(-50, ph::DriveForOutput(pp::FingerKind::kJamming, nominal, 1.0), 1e-6);
  ph::FingerCurves calibrated;
  calibrated.calibrated = {{0, 0}, {10, 0.2}, {40, 2.0}};
  DOUBLES_EQUAL(25, ph::DriveForOutput(pp::FingerKind::kPneumatic, calibrated, 1.1), 1e-6);
}

TEST(ScenePredict, EvenMotionLeadsByVelocityTimesHorizon) {
  ph::MotionPredictor p(Options(0.02));
  ph::SceneInput out;
  for (int k = 0; k < 3; ++k) out = p.Next(At(k, 30));
  // Horizon plus half the 10 ms sample interval: 25 ms at 30 mm/s is 0.75 mm.
  for (int k = 3; k < 20; ++k) {
    out = p.Next(At(k, 30));
    CHECK_EQUAL(ph::Prediction::kPredicted, p.last());
    DOUBLES_EQUAL(At(k, 30).x_mm + 0.75, out.x_mm, 1e-9);
    DOUBLES_EQUAL(15, out.y_mm, 1e-9);
    DOUBLES_EQUAL(1, out.force_n, 0);
    DOUBLES_EQUAL(0.75, p.last_lead_mm(), 1e-9);
  }
  // Diagonal: the lead along the motion.
  ph::MotionPredictor d(Options(0.02));
  for (int k = 0; k < 10; ++k) out = d.Next({k * 0.01, 10 + 0.3 * k, 10 + 0.4 * k, 1});
  DOUBLES_EQUAL(10 + 0.3 * 9 + 30 * 0.025, out.x_mm, 1e-9);
  DOUBLES_EQUAL(10 + 0.4 * 9 + 40 * 0.025, out.y_mm, 1e-9);
}

TEST(ScenePredict, FirstSamplesNotPredicted) {
  ph::MotionPredictor p(Options(0.02));
  DOUBLES_EQUAL(20, p.Next(At(0, 30)).x_mm, 0);
  CHECK_EQUAL(ph::Prediction::kTooFewSamples, p.last());
  p.Next(At(1, 30));
  CHECK_EQUAL(ph::Prediction::kTooFewSamples, p.last());
}

TEST(ScenePredict, LeadCappedAndHeldOnTheTissue) {
  ph::MotionPredictor fast(Options(0.05));
  ph::SceneInput out;
  for (int k = 0; k < 6; ++k) out = fast.Next(At(k, 400));  // 400 mm/s × 55 ms = 22 mm
  DOUBLES_EQUAL(2.0, fast.last_lead_mm(), 1e-9);
  DOUBLES_EQUAL(At(5, 400).x_mm + 2, out.x_mm, 1e-9);
  ph::MotionPredictor edge(Options(0.02));
  edge.SetExtent(120, 30);
  for (int k = 0; k < 6; ++k) out = edge.Next(At(k, 30, 119));
  // Past the edge already (120.5 mm): a sample off the tissue is not held on it.
  DOUBLES_EQUAL(At(5, 30, 119).x_mm + 0.75, out.x_mm, 1e-9);
  ph::MotionPredictor inside(Options(0.02));
  inside.SetExtent(120, 30);
  for (int k = 0; k < 6; ++k) out = inside.Next(At(k, 30, 118.0));
  DOUBLES_EQUAL(119.5, At(5, 30, 118).x_mm, 1e-9);
  DOUBLES_EQUAL(120, out.x_mm, 1e-9);  // 119.5 + 0.75 held at the tissue's edge
}

TEST(ScenePredict, ReversalNotPredicted) {
  ph::MotionPredictor p(Options(0.03));
  ph::SceneInput out;
  for (int k = 0; k < 10; ++k) out = p.Next(At(k, 30));
  const double turn = At(9, 30).x_mm;
  bool reversing_seen = false;
  // Back at 30 mm/s: until the window holds the new motion alone, nothing is predicted, and a
  // prediction never lies beyond the turning point in the old direction.
  for (int k = 1; k < 12; ++k) {
    out = p.Next({(9 + k) * 0.01, turn - 0.3 * k, 15, 1});
    reversing_seen |= p.last() == ph::Prediction::kReversing;
    CHECK(out.x_mm <= turn + 1e-9);
    if (p.last() == ph::Prediction::kPredicted) CHECK(out.x_mm < turn - 0.3 * k);
  }
  CHECK(reversing_seen);
  CHECK_EQUAL(ph::Prediction::kPredicted, p.last());  // the new motion, once it is the whole window
}

TEST(ScenePredict, StopNotOvershotByMoreThanTheDecelerationAllows) {
  ph::MotionPredictor p(Options(0.03));
  for (int k = 0; k < 10; ++k) p.Next(At(k, 30));
  const double stop = At(9, 30).x_mm;
  ph::SceneInput out;
  double worst = 0;
  for (int k = 1; k < 10; ++k) {
    out = p.Next({(9 + k) * 0.01, stop, 15, 1});
    worst = std::max(worst, out.x_mm - stop);
  }
  CHECK_EQUAL(ph::Prediction::kStopped, p.last());
  DOUBLES_EQUAL(stop, out.x_mm, 0);
  // At worst the first sample of the stop: the slower half-window's speed (a third of the
  // window at 30 mm/s) over the horizon — less than the 1.05 mm the full speed would give.
  CHECK(worst < 0.6);
}

TEST(ScenePredict, NoisyInputFallsBack) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.3);
  ph::MotionPredictor p(Options(0.03));
  int predicted = 0;
  for (int k = 0; k < 200; ++k) {
    ph::SceneInput s = At(k, 10);
    s.x_mm += noise(rng), s.y_mm += noise(rng);
    const ph::SceneInput out = p.Next(s);
    if (p.last() == ph::Prediction::kPredicted) {
      ++predicted;
      CHECK(std::hypot(out.x_mm - s.x_mm, out.y_mm - s.y_mm) <= 2.0 + 1e-9);
    } else {
      DOUBLES_EQUAL(s.x_mm, out.x_mm, 0);
    }
  }
  CHECK(predicted < 20);  // 0.3 mm of jitter is erratic against a 0.15 mm straight-line fit
}

TEST(ScenePredict, GapsAndLiftsStartAfresh) {
  ph::MotionPredictor p(Options(0.02));
  for (int k = 0; k < 5; ++k) p.Next(At(k, 30));
  CHECK_EQUAL(ph::Prediction::kPredicted, p.last());
  p.Next({0.5, 40, 15, 1});  // 0.46 s later: a new motion
  CHECK_EQUAL(ph::Prediction::kTooFewSamples, p.last());
  ph::MotionPredictor lifted(Options(0.02));
  for (int k = 0; k < 5; ++k) lifted.Next(At(k, 30));
  const ph::SceneInput up{0.05, 21.5, 15, 0};
  DOUBLES_EQUAL(21.5, lifted.Next(up).x_mm, 0);
  CHECK_EQUAL(ph::Prediction::kLifted, lifted.last());
}

TEST(ScenePredict, BadOptionsNamed) {
  ph::PredictorOptions o = Options(2);
  STRCMP_CONTAINS("horizon 2 s is outside 0 … 1 s", ph::CheckPredictor(o).message.c_str());
  o = Options(0.02);
  o.window_s = 0;
  STRCMP_CONTAINS("window 0 s", ph::CheckPredictor(o).message.c_str());
  o = Options(0.02);
  o.max_lead_mm = -1;
  STRCMP_CONTAINS("lead -1 mm", ph::CheckPredictor(o).message.c_str());
  CHECK(ph::CheckPredictor(Options(0.02)).ok());
}
