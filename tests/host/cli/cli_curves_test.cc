// palpa set with a calibration file beside the board's static inverse: a file the board holds is
// used without a word; one edited beyond its fit residual is named with the board's curve, on
// stderr and in --json, and the board's curve is followed.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixtures.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::Has;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP_BASE(CliCurves, palpa::testing::SimBoardGroup){
    /// palpa set 1=L1 with DIR/PN-1.json the test data file `name`.
    Run SetWith(const std::string& name, const std::string& json = ""){
        std::filesystem::copy_file(std::string(PALPA_TEST_DATA_DIR) + "/" + name,
                                   dir + "/PN-1.json",
                                   std::filesystem::copy_options::overwrite_existing);
return Palpa(device + json + "set 1=L1", "PALPA_CALIBRATION_DIR=" + dir, json.empty());
}
}
;

TEST(CliCurves, AFileTheBoardHoldsIsUsedWithoutAWarning) {
  const Run r = SetWith("curve_on_board.json");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "through calibration of PN-1"), r.output.c_str());
  CHECK_FALSE_TEXT(Has(r, "warning"), r.output.c_str());
}

TEST(CliCurves, AFileEditedBeyondItsResidualIsNamedBesideTheBoard) {
  const std::string file = dir + "/PN-1.json";
  Run r = SetWith("curve_off_board.json");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "palpa: warning: finger 1: calibration file " + file +
                        " disagrees with the board's static inverse for finger 1 (the nominal "
                        "one) by 40 µm at 70.1 kPa, more than the file's fit residual (12 µm RMS)"),
             r.output.c_str());
  CHECK_TEXT(Has(r, "through the board's static inverse for finger 1 (the nominal one); " + file +
                        " disagrees with it"),
             r.output.c_str());
  r = SetWith("curve_off_board.json", "--json ");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const auto out = nlohmann::json::parse(r.output);
  const auto& w = out["curve_warnings"][0];
  LONGS_EQUAL(1, w["finger"].get<int>());
  STRCMP_EQUAL(file.c_str(), w["file"].get<std::string>().c_str());
  DOUBLES_EQUAL(40, w["disagreement"].get<double>(), 1e-9);
  // --strict-calibration: a file requests would not go through is refused, nothing sent.
  r = Palpa(device + "set --strict-calibration 1=L1", "PALPA_CALIBRATION_DIR=" + dir);
  LONGS_EQUAL_TEXT(1, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "disagrees with the board's static inverse"), r.output.c_str());
}
