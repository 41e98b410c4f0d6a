// What applying a calibration makes of a finger's and its lines' records (CalibratedFinger,
// CalibratedLine): every calibrated field, the fields left as the board had them, and refusals.
#include <string>

#include "example_calibration.h"
#include "palpa/host/calibration_file.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

/// A finger record as a board holds it before calibration: nominal curve, no compensator.
pp::ConfigureFinger BoardFinger(pp::FingerKind kind) {
  pp::ConfigureFinger f;
  f.finger = 2;
  f.kind = kind;
  f.line_a = 3;
  f.line_b = kind == pp::FingerKind::kJamming ? 4 : pp::kNoLine;
  f.bias_pa = 15000;
  f.actuator_serial = {'P', 'N', '-', '1'};
  f.inverse_count = 6;
  for (int32_t k = 0; k < 6; ++k) f.inverse[k] = {1000 * k, 20000 * k};
  f.param_count = 0;
  return f;
}

/// A line record as a board holds it: a slew limit, no correction, no chamber model.
pp::ConfigureLine BoardLine(uint8_t index) {
  pp::ConfigureLine l;
  l.line = index;
  l.slew_pa_per_s = 400000;
  l.model_tau_us = 20000;
  l.correction_count = 1;
  l.correction[0] = {0, 1, 2};
  return l;
}

}  // namespace

TEST_GROUP(CalibrationApply){};

TEST(CalibrationApply, TheFingerTakesTheInverseAndCompensatorAndKeepsTheRest) {
  const ph::CalibrationFile c = palpa::testing::ExampleCalibration();
  const auto made = ph::CalibratedFinger(BoardFinger(pp::FingerKind::kPneumatic), c);
  CHECK_TEXT(made.ok(), made.message.c_str());
  const pp::ConfigureFinger& f = made.value;
  LONGS_EQUAL(5, f.inverse_count);  // the file's five points, not the board's six
  for (size_t k = 0; k < 5; ++k) {
    LONGS_EQUAL(c.static_inverse[k].output, f.inverse[k].output);
    LONGS_EQUAL(c.static_inverse[k].setpoint_pa, f.inverse[k].setpoint_pa);
  }
  CHECK(f.compensator == pp::CompensatorKind::kPrandtlIshlinskii);
  LONGS_EQUAL(6, f.param_count);
  for (size_t k = 0; k < 6; ++k) DOUBLES_EQUAL(c.compensator_params[k], f.params[k], 0);
  // What the calibration does not speak of stays the board's.
  LONGS_EQUAL(2, f.finger);
  LONGS_EQUAL(3, f.line_a);
  LONGS_EQUAL(pp::kNoLine, f.line_b);
  STRCMP_EQUAL("PN-1", f.actuator_serial.data());
  // A pneumatic finger has no bias to take, whatever the file recommends.
  ph::CalibrationFile biased = c;
  biased.recommended_bias_pa = 30000;
  LONGS_EQUAL(15000,
              ph::CalibratedFinger(BoardFinger(pp::FingerKind::kPneumatic), biased).value.bias_pa);
}

TEST(CalibrationApply, AJammingFingerTakesTheRecommendedBiasRoundedOrKeepsItsOwn) {
  ph::CalibrationFile c = palpa::testing::ExampleJammingCalibration();
  c.recommended_bias_pa = 20499.6;
  const auto made = ph::CalibratedFinger(BoardFinger(pp::FingerKind::kJamming), c);
  CHECK_TEXT(made.ok(), made.message.c_str());
  LONGS_EQUAL(20500, made.value.bias_pa);
  CHECK(made.value.compensator == pp::CompensatorKind::kAsymmetricPi);
  LONGS_EQUAL(9, made.value.param_count);
  LONGS_EQUAL(3, made.value.inverse_count);
  LONGS_EQUAL(-100000, made.value.inverse[2].setpoint_pa);
  c.recommended_bias_pa.reset();
  LONGS_EQUAL(15000, ph::CalibratedFinger(BoardFinger(pp::FingerKind::kJamming), c).value.bias_pa);
}

TEST(CalibrationApply, AFingerRefusesAnotherKindAndMoreThanItsRecordHolds) {
  const ph::CalibrationFile c = palpa::testing::ExampleCalibration();
  const auto other = ph::CalibratedFinger(BoardFinger(pp::FingerKind::kJamming), c);
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)other.status);
  STRCMP_CONTAINS("kind differs", other.message.c_str());
  // At the record's capacity it is taken; one more is refused, not written past the record.
  ph::CalibrationFile full = c;
  full.static_inverse.resize(pp::kMaxInversePoints);
  full.compensator_params.resize(pp::kMaxCompensatorParams);
  const auto fits = ph::CalibratedFinger(BoardFinger(pp::FingerKind::kPneumatic), full);
  CHECK_TEXT(fits.ok(), fits.message.c_str());
  LONGS_EQUAL(pp::kMaxInversePoints, fits.value.inverse_count);
  LONGS_EQUAL(pp::kMaxCompensatorParams, fits.value.param_count);
  ph::CalibrationFile points = full;
  points.static_inverse.push_back({});
  const auto too_many = ph::CalibratedFinger(BoardFinger(pp::FingerKind::kPneumatic), points);
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)too_many.status);
  STRCMP_CONTAINS("static inverse has 17 points, a finger holds 16", too_many.message.c_str());
  ph::CalibrationFile params = full;
  params.compensator_params.push_back(0);
  const auto too_long = ph::CalibratedFinger(BoardFinger(pp::FingerKind::kPneumatic), params);
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)too_long.status);
  STRCMP_CONTAINS("81 parameters, a finger holds 80", too_long.message.c_str());
}

TEST(CalibrationApply, ALineTakesItsCorrectionAndChamberModelOnlyWhereTheFileHasThem) {
  const ph::CalibrationFile c = palpa::testing::ExampleJammingCalibration();
  // Line 3: a correction and no chamber model: corrected, steps not shaped.
  pp::ConfigureLine three = BoardLine(3);
  auto changed = ph::CalibratedLine(c, 3, three);
  CHECK_TEXT(changed.ok() && changed.value, changed.message.c_str());
  LONGS_EQUAL(2, three.correction_count);
  LONGS_EQUAL(18000, three.correction[1].command_pa);
  LONGS_EQUAL(18050, three.correction[1].rising_pa);
  LONGS_EQUAL(17950, three.correction[1].falling_pa);
  LONGS_EQUAL(0, three.chamber_tau_us);
  LONGS_EQUAL(400000, three.slew_pa_per_s);
  // Line 4: a correction and a chamber model: shaped, the slew limit off, the model's lag in µs.
  pp::ConfigureLine four = BoardLine(4);
  changed = ph::CalibratedLine(c, 4, four);
  CHECK_TEXT(changed.ok() && changed.value, changed.message.c_str());
  LONGS_EQUAL(-90000, four.correction[1].command_pa);
  LONGS_EQUAL(30000, four.chamber_tau_us);
  LONGS_EQUAL(ph::kShapingOverdrivePa, four.overdrive_pa);
  LONGS_EQUAL(0, four.slew_pa_per_s);
  LONGS_EQUAL(20000, four.model_tau_us);  // the regulator model is the board's
  // A chamber model alone: shaped, the board's correction kept.
  ph::CalibrationFile chamber_only = c;
  chamber_only.regulator_corrections.clear();
  pp::ConfigureLine shaped = BoardLine(4);
  changed = ph::CalibratedLine(chamber_only, 4, shaped);
  CHECK(changed.ok() && changed.value);
  LONGS_EQUAL(1, shaped.correction_count);
  LONGS_EQUAL(30000, shaped.chamber_tau_us);
  // Line 5: nothing in the file: false, the record untouched.
  pp::ConfigureLine five = BoardLine(5);
  changed = ph::CalibratedLine(c, 5, five);
  CHECK(changed.ok());
  CHECK_FALSE(changed.value);
  LONGS_EQUAL(1, five.correction_count);
  LONGS_EQUAL(400000, five.slew_pa_per_s);
}

TEST(CalibrationApply, ALineRefusesACorrectionLongerThanItsRecordAndIsLeftUntouched) {
  ph::CalibrationFile c = palpa::testing::ExampleCalibration();
  c.regulator_corrections[0].points.assign(pp::kMaxCorrectionPoints, {1000, 1000, 1000});
  pp::ConfigureLine line = BoardLine(0);
  auto changed = ph::CalibratedLine(c, 0, line);
  CHECK_TEXT(changed.ok() && changed.value, changed.message.c_str());
  LONGS_EQUAL(pp::kMaxCorrectionPoints, line.correction_count);
  c.regulator_corrections[0].points.push_back({});
  line = BoardLine(0);
  changed = ph::CalibratedLine(c, 0, line);
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)changed.status);
  STRCMP_CONTAINS("line 0's correction has 13 points, a line holds 12", changed.message.c_str());
  LONGS_EQUAL(1, line.correction_count);
  LONGS_EQUAL(0, line.chamber_tau_us);  // nothing of it applied, not even the chamber model
}
