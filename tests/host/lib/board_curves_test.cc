// One curve per finger: the host follows the static inverse its board holds, and a calibration
// file that disagrees with the board by more than its fit residual is named in a warning.
#include <cstdlib>
#include <string>

#include "example_calibration.h"
#include "palpa/host/board_curves.h"
#include "palpa/host/device.h"

#include "CppUTest/TestHarness.h"
#include "temp_dir.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

pp::ConfigureFinger WithInverse(const ph::CalibrationFile& c) {
  pp::ConfigureFinger f{};
  f.kind = c.kind;
  f.inverse_count = static_cast<uint8_t>(c.static_inverse.size());
  std::copy(c.static_inverse.begin(), c.static_inverse.end(), f.inverse.begin());
  return f;
}

/// A device on a fresh simulated board whose finger 0 holds `held`'s static inverse, looking for
/// calibrations in a directory holding `file`.
std::unique_ptr<ph::Device> OpenWith(const ph::CalibrationFile& held,
                                     const ph::CalibrationFile& file, std::string& dir) {
  dir = palpa::testing::MakeTempDir("palpa-curves");
  const ph::Outcome saved = ph::SaveCalibration(file, ph::CalibrationPath(dir, "PN-1"));
  CHECK_TEXT(saved.ok(), saved.message.c_str());
  ph::DeviceOptions options;
  options.calibration_dir = dir;
  auto opened = ph::Device::Open("sim:thesis-5finger", options);
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  // Before anything looks the calibrations up: the board holds `held`'s inverse from now on.
  pp::ConfigureFinger f = opened.value->ReadFinger(0).value;
  f.inverse_count = static_cast<uint8_t>(held.static_inverse.size());
  std::copy(held.static_inverse.begin(), held.static_inverse.end(), f.inverse.begin());
  const ph::Outcome o = opened.value->ConfigureFinger(f);
  CHECK_TEXT(o.ok(), o.message.c_str());
  return std::move(opened.value);
}

}  // namespace

TEST_GROUP(BoardCurves){};

TEST(BoardCurves, TheCompiledInInversesAreTheNominalCurves) {
  pp::ConfigureFinger pneumatic{};
  pneumatic.kind = pp::FingerKind::kPneumatic;
  pneumatic.inverse_count = 5;
  pneumatic.inverse = {{{0, 4581}, {1000, 26415}, {2000, 48249}, {3000, 70083}, {4370, 100000}}};
  CHECK(ph::IsNominalInverse(pneumatic));
  CHECK(ph::CurvesFromBoard(pneumatic, "x").calibrated.empty());  // the nominal line, not points
  pneumatic.inverse[2].setpoint_pa += 200;                        // 9 µm off the line
  CHECK_FALSE(ph::IsNominalInverse(pneumatic));
  pp::ConfigureFinger jamming{};
  jamming.kind = pp::FingerKind::kJamming;
  jamming.inverse_count = 3;
  jamming.inverse = {{{700, 0}, {1000, -50000}, {1300, -100000}}};
  CHECK(ph::IsNominalInverse(jamming));
}

TEST(BoardCurves, TheBoardsInverseIsTheCalibrationsCurveWhenItHoldsIt) {
  const ph::CalibrationFile c = palpa::testing::ExampleCalibration();
  const ph::FingerCurves board = ph::CurvesFromBoard(WithInverse(c), "board");
  const ph::FingerCurves file = ph::CurvesFromCalibration(c);
  CHECK(board.calibrated == file.calibrated);
  DOUBLES_EQUAL(file.max_deformation_mm, board.max_deformation_mm, 0);
  const ph::CurveComparison same = ph::CompareWithBoard(c, WithInverse(c));
  CHECK(same.overlap);
  DOUBLES_EQUAL(0, same.disagreement, 0);
  ph::CalibrationFile edited = c;
  edited.curve[3].output += 50;  // 60 kPa
  const ph::CurveComparison off = ph::CompareWithBoard(edited, WithInverse(c));
  DOUBLES_EQUAL(50, off.disagreement, 1e-9);
  DOUBLES_EQUAL(60000, off.at_pa, 0);
  // Between points too: the board's line from 30 to 100 kPa against a file with a knee at 60.
  ph::CalibrationFile fewer = c;
  fewer.static_inverse.erase(fewer.static_inverse.begin() + 3);
  DOUBLES_EQUAL(2600 - (1200 + 3000.0 * 3 / 7),
                ph::CompareWithBoard(c, WithInverse(fewer)).disagreement, 1e-9);
}

TEST(BoardCurves, AFileTheBoardHoldsGivesNoWarning) {
  const ph::CalibrationFile c = palpa::testing::ExampleCalibration();
  std::string dir;
  auto d = OpenWith(c, c, dir);
  CHECK(d->curve_warnings().empty());
  STRCMP_CONTAINS("calibration of PN-1", d->calibration_notes()[0].c_str());
  CHECK(d->curves(0).calibrated == ph::CurvesFromCalibration(c).calibrated);
  // Within its residual (12 µm RMS) a file still agrees.
  ph::CalibrationFile near = c;
  near.curve[3].output += 10;
  d = OpenWith(c, near, dir);
  CHECK(d->curve_warnings().empty());
}

TEST(BoardCurves, AFileEditedBeyondItsResidualIsNamedBesideTheBoard) {
  const ph::CalibrationFile c = palpa::testing::ExampleCalibration();
  ph::CalibrationFile edited = c;
  edited.curve[3].output += 50;
  edited.static_inverse[3].output += 50;
  std::string dir;
  auto d = OpenWith(c, edited, dir);
  LONGS_EQUAL(1, d->curve_warnings().size());
  const ph::CurveWarning& w = d->curve_warnings()[0];
  LONGS_EQUAL(0, w.finger);
  STRCMP_EQUAL((dir + "/PN-1.json").c_str(), w.file.c_str());
  DOUBLES_EQUAL(50, w.disagreement, 1e-9);
  DOUBLES_EQUAL(12, w.residual, 0);
  STRCMP_CONTAINS(w.file.c_str(), w.message.c_str());
  STRCMP_CONTAINS("the board's static inverse for finger 0 (5 points)", w.message.c_str());
  STRCMP_CONTAINS("by 50 µm at 60.0 kPa, more than the file's fit residual (12 µm RMS)",
                  w.message.c_str());
  // Requests go through what the board holds, and say so.
  CHECK(d->curves(0).calibrated == ph::CurvesFromCalibration(c).calibrated);
  STRCMP_CONTAINS("disagrees with it", d->calibration_notes()[0].c_str());
  // Applying the file makes the board hold it: the warning is gone, the curve is the file's.
  const ph::Outcome o = d->ApplyCalibration(0, edited);
  CHECK_TEXT(o.ok(), o.message.c_str());
  CHECK(d->curve_warnings().empty());
  CHECK(d->curves(0).calibrated == ph::CurvesFromCalibration(edited).calibrated);
}

TEST(BoardCurves, ACalibrationNotOnItsNominalBoardIsNamedAndTheNominalCurveFollowed) {
  const std::string dir = palpa::testing::MakeTempDir("palpa-curves");
  CHECK(ph::SaveCalibration(palpa::testing::ExampleCalibration(), ph::CalibrationPath(dir, "PN-1"))
            .ok());
  ph::DeviceOptions options;
  options.calibration_dir = dir;
  auto opened = ph::Device::Open("sim:thesis-5finger", options);
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  ph::Device& d = *opened.value;
  LONGS_EQUAL(1, d.curve_warnings().size());
  STRCMP_CONTAINS("the board's static inverse for finger 0 (the nominal one)",
                  d.curve_warnings()[0].message.c_str());
  CHECK(d.curves(0).calibrated.empty());  // the nominal line the board's inverse is
}
