// Calibration files: a round trip, every kind of bad field named by its path, atomic writes,
// lookup by serial, the stiffness map on calibrated curves, and upload to a simulated board.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "example_calibration.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/device.h"

#include "CppUTest/TestHarness.h"
#include "temp_dir.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using nlohmann::json;

namespace {

ph::CalibrationFile Example() { return palpa::testing::ExampleCalibration(); }

std::string ErrorAfter(const std::function<void(json&)>& edit) {
  json j = json::parse(ph::SerializeCalibration(Example()).value);
  edit(j);
  const auto parsed = ph::ParseCalibration(j.dump());
  CHECK_FALSE(parsed.ok());
  LONGS_EQUAL((int)pp::Status::kInvalidArgument, (int)parsed.status);
  return parsed.message;
}

}  // namespace

TEST_GROUP(CalibrationFile){};

TEST(CalibrationFile, SavesAtomicallyAndReadsBackEveryField) {
  const std::string dir = palpa::testing::MakeTempDir("palpa-cal");
  const ph::Outcome saved = ph::SaveCalibration(Example(), ph::CalibrationPath(dir, "PN-1"));
  CHECK_TEXT(saved.ok(), saved.message.c_str());
  const auto found = ph::FindCalibration(dir, "PN-1");
  CHECK_TEXT(found.ok(), found.message.c_str());
  const ph::CalibrationFile* back = &found.value;
  STRCMP_EQUAL("PN-1", back->actuator_serial.c_str());
  LONGS_EQUAL(5, back->curve.size());
  DOUBLES_EQUAL(1200, back->curve[2].output, 1e-12);
  DOUBLES_EQUAL(30000, back->curve[2].drive_pa, 1e-12);
  LONGS_EQUAL(2, back->simulation->actuator_unit);
  STRCMP_EQUAL("creep,rate", back->simulation->effects.c_str());
  LONGS_EQUAL(30000, back->static_inverse[2].setpoint_pa);
  LONGS_EQUAL(49500, back->regulator_corrections[0].points[1].falling_pa);
  LONGS_EQUAL(1, back->chamber_models.size());
  DOUBLES_EQUAL(0.005, back->chamber_models[0].chamber_tau_s, 1e-12);
  DOUBLES_EQUAL(0.0035, back->chamber_models[0].tube_tau_s, 1e-12);
  DOUBLES_EQUAL(0.015, back->chamber_models[0].tube_fit_rms, 1e-12);
  STRCMP_EQUAL("", ph::ChamberNote(*back).c_str());
  CHECK(back->compensator == pp::CompensatorKind::kPrandtlIshlinskii);
  LONGS_EQUAL(6, back->compensator_params.size());
  DOUBLES_EQUAL(0.98, back->falling_fit->r2, 1e-12);
  STRCMP_EQUAL("adaptive", back->quality.protocol.c_str());
  LONGS_EQUAL(17, back->quality.cycles);
  DOUBLES_EQUAL(1234.5, back->quality.rig_time_s, 1e-9);
  DOUBLES_EQUAL(0.021, *back->quality.map_error, 1e-12);
  LONGS_EQUAL(5, back->quality.checks.size());
  STRCMP_EQUAL("leak", back->quality.checks[3].name.c_str());
  CHECK_FALSE(back->quality.checks[3].passed);
  DOUBLES_EQUAL(1.7, back->quality.checks[3].value, 1e-12);
  // Only the file itself is in the directory: the temporary was renamed over it.
  LONGS_EQUAL(0, std::system(("test \"$(ls -A " + dir + ")\" = PN-1.json").c_str()));
  // An invalid calibration writes nothing, and the good file stays as it was.
  ph::CalibrationFile bad = Example();
  bad.static_inverse[1].setpoint_pa = 50000;  // no longer increasing
  const ph::Outcome refused = ph::SaveCalibration(bad, ph::CalibrationPath(dir, "PN-1"));
  CHECK_FALSE(refused.ok());
  CHECK(refused.message.find("static_inverse.setpoint_pa[2]") != std::string::npos);
  CHECK(ph::FindCalibration(dir, "PN-1").ok());
  auto missing = ph::FindCalibration(dir, "PN-2");
  LONGS_EQUAL((int)pp::Status::kNotFound, (int)missing.status);
  CHECK(missing.message.find("no calibration for PN-2") != std::string::npos);
  missing = ph::FindCalibration(dir, "../etc");
  LONGS_EQUAL((int)pp::Status::kNotFound, (int)missing.status);
  CHECK(missing.message.find("cannot name") != std::string::npos);
  // A file that is there but invalid is told apart from no file.
  std::ofstream(ph::CalibrationPath(dir, "PN-3")) << "{}";
  missing = ph::FindCalibration(dir, "PN-3");
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)missing.status);
  CHECK(missing.message.find("PN-3.json: schema: missing") != std::string::npos);
}

TEST(CalibrationFile, AVersion2FileIsReadWithANoteThatItsStepsAreNotShaped) {
  json j = json::parse(ph::SerializeCalibration(Example()).value);
  j["schema_version"] = 2;
  j.erase("chamber_models");
  const auto c = ph::ParseCalibration(j.dump());
  CHECK_TEXT(c.ok(), c.message.c_str());
  LONGS_EQUAL(2, c.value.schema_version);
  CHECK(c.value.chamber_models.empty());
  STRCMP_EQUAL(
      "schema version 2 has no chamber model: steps are not shaped until the finger is "
      "calibrated again",
      ph::ChamberNote(c.value).c_str());
  // Written again it is a version 3 file, still without a chamber model.
  const auto again = ph::ParseCalibration(ph::SerializeCalibration(c.value).value);
  CHECK_TEXT(again.ok(), again.message.c_str());
  LONGS_EQUAL(ph::kCalibrationSchemaVersion, again.value.schema_version);
  STRCMP_EQUAL("no chamber model: steps are not shaped", ph::ChamberNote(again.value).c_str());
}

TEST(CalibrationFile, AVersion3ChamberModelLoadsWithANoteAndShapesNothing) {
  // Version 3's chamber_tau_s is the lag behind the regulator model; the board now reads
  // chamber_tau_us as the lag behind the outlet through the tube's law. Never reinterpreted.
  json j = json::parse(ph::SerializeCalibration(Example()).value);
  j["schema_version"] = 3;
  j["chamber_models"][0].erase("tube_tau_s");
  j["chamber_models"][0].erase("tube_fit_rms");
  const auto c = ph::ParseCalibration(j.dump());
  CHECK_TEXT(c.ok(), c.message.c_str());
  LONGS_EQUAL(1, c.value.chamber_models.size());
  DOUBLES_EQUAL(0.005, c.value.chamber_models[0].chamber_tau_s, 1e-12);
  DOUBLES_EQUAL(0, c.value.chamber_models[0].tube_tau_s, 0);
  STRCMP_EQUAL(
      "the chamber model of line 0 is a lag behind the regulator (schema version 3), not the "
      "tube's the board shapes with: steps are not shaped until the finger is calibrated again",
      ph::ChamberNote(c.value).c_str());
  // Applied, the line takes its correction and no chamber model: no lag, no overdrive.
  pp::ConfigureLine line{};
  line.slew_pa_per_s = 200000;
  const auto changed = ph::CalibratedLine(c.value, 0, line);
  CHECK_TEXT(changed.ok() && changed.value, changed.message.c_str());
  LONGS_EQUAL(3, line.correction_count);
  LONGS_EQUAL(0, line.chamber_tau_us);
  LONGS_EQUAL(0, line.overdrive_pa);
  LONGS_EQUAL(200000, line.slew_pa_per_s);
  // Written again it is a version 4 file whose model still has no tube lag, and says so.
  const auto again = ph::ParseCalibration(ph::SerializeCalibration(c.value).value);
  CHECK_TEXT(again.ok(), again.message.c_str());
  LONGS_EQUAL(ph::kCalibrationSchemaVersion, again.value.schema_version);
  DOUBLES_EQUAL(0, again.value.chamber_models[0].tube_tau_s, 0);
  STRCMP_CONTAINS("steps are not shaped", ph::ChamberNote(again.value).c_str());
  // A version 3 file cannot carry a tube lag: the field is refused, not read in the old sense.
  j["chamber_models"][0]["tube_tau_s"] = 0.004;
  const auto refused = ph::ParseCalibration(j.dump());
  CHECK_FALSE(refused.ok());
  STRCMP_CONTAINS("chamber_models[0].tube_tau_s: unknown field", refused.message.c_str());
}

TEST(CalibrationFile, EveryBadFieldIsNamedByItsPath) {
  struct Case {
    std::function<void(json&)> edit;
    const char* names;
  };
  const Case cases[] = {
      {[](json& j) { j.erase("date"); }, "date: missing"},
      {[](json& j) { j["date"] = "yesterday"; }, "date: must be UTC"},
      {[](json& j) { j["colour"] = "red"; }, "colour: unknown field"},
      {[](json& j) { j["schema_version"] = 5; }, "schema_version: 5 is not"},
      {[](json& j) { j["recommended_bias_kpa"] = 20; },
       "recommended_bias_kpa: unknown field in schema version 4"},
      {[](json& j) { j["chamber_models"][0]["tube_tau_s"] = 0; },
       "chamber_models[0].tube_tau_s: 0 is outside"},
      {[](json& j) { j["chamber_models"][0].erase("tube_fit_rms"); },
       "chamber_models[0].tube_fit_rms: missing"},
      {[](json& j) { j["chamber_models"][0].erase("tube_tau_s"); },
       "chamber_models[0].tube_tau_s: missing"},
      {[](json& j) { j["schema_version"] = 2; },
       "chamber_models: unknown field in schema version 2"},
      {[](json& j) { j["chamber_models"][0]["chamber_tau_s"] = 0; },
       "chamber_models[0].chamber_tau_s: 0 is outside"},
      {[](json& j) { j["chamber_models"][0]["fit_rms"] = 2; }, "chamber_models[0].fit_rms"},
      {[](json& j) { j["chamber_models"][0].erase("dead_time_s"); },
       "chamber_models[0].dead_time_s: missing"},
      {[](json& j) { j["chamber_models"].push_back(j["chamber_models"][0]); },
       "chamber_models[1].line: line 0 appears twice"},
      {[](json& j) { j["simulation"]["effects"] = "creep,wind"; }, "simulation.effects"},
      {[](json& j) { j["simulation"]["plant_level"] = 4; }, "simulation.plant_level: 4"},
      {[](json& j) { j["actuator_serial"] = "a/b"; }, "actuator_serial"},
      {[](json& j) { j["kind"] = "hydraulic"; }, "kind: must be"},
      {[](json& j) { j["finger"] = 9; }, "finger: 9 is outside 0"},
      {[](json& j) { j["conditions"]["speed_um_s"] = 0; }, "conditions.speed_um_s"},
      {[](json& j) { j["conditions"]["speed_mm_s"] = 0.1; }, "conditions.speed_mm_s: unknown"},
      {[](json& j) { j["raw_data"] = "../../x.csv"; }, "raw_data"},
      {[](json& j) { j["curve"][2]["output"] = 0.1; }, "curve.output[2]: not strictly increasing"},
      {[](json& j) { j["curve"][1]["drive_pa"] = "ten"; }, "curve[1].drive_pa: must be a number"},
      {[](json& j) { j["curve"][4]["drive_pa"] = 100001; }, "curve[4].drive_pa: 100001 is outside"},
      {[](json& j) { j["static_inverse"][3]["setpoint_pa"] = -120000; },
       "static_inverse[3].setpoint_pa: -120000 is outside"},
      {[](json& j) {
         j["static_inverse"] = json::array({{{"output", 0}, {"setpoint_pa", 0}}});
       },
       "static_inverse: has 1 entries"},
      {[](json& j) { j["regulator_corrections"][0]["line"] = 8; }, "regulator_corrections[0].line"},
      {[](json& j) { j["regulator_corrections"][0]["points"][1]["rising_pa"] = 0; },
       "regulator_corrections[0].points.rising_pa[1]"},
      {[](json& j) { j["regulator_corrections"].push_back(j["regulator_corrections"][0]); },
       "regulator_corrections[1].line: line 0 appears twice"},
      {[](json& j) { j["compensator"]["kind"] = "magic"; }, "compensator.kind: unknown"},
      {[](json& j) { j["compensator"]["params"][5] = -0.1; },
       "compensator.params: cumulative weight"},
      {[](json& j) { j["compensator"]["params"][1] = "x"; },
       "compensator.params[1]: must be a finite number"},
      {[](json& j) { j["fits"]["rising"]["r2"] = 1.5; }, "fits.rising.r2"},
      {[](json& j) { j["quality"]["flags"] = json::array({1}); }, "quality.flags[0]"},
      {[](json& j) { j["quality"]["protocol"] = "quick"; }, "quality.protocol"},
      {[](json& j) { j["quality"]["checks"][0]["passed"] = "yes"; },
       "quality.checks[0].passed: must be true or false"},
      {[](json& j) { j["quality"]["checks"][1].erase("limit"); },
       "quality.checks[1].limit: missing"},
      {[](json& j) { j["quality"]["checks"][1]["unit"] = "N"; },
       "quality.checks[1].unit: a noise check is in mN"},
      {[](json& j) { j["quality"]["checks"][1]["name"] = "wind"; }, "quality.checks[1].name"},
      {[](json& j) { j["quality"]["map_error"] = -0.1; }, "quality.map_error"},
      {[](json& j) { j["kind"] = "jamming"; }, "conditions.bias_pa: missing"},
  };
  for (const Case& c : cases) {
    const std::string error = ErrorAfter(c.edit);
    CHECK_TEXT(error.find(c.names) != std::string::npos,
               (std::string("expected '") + c.names + "' in '" + error + "'").c_str());
  }
  const auto not_json = ph::ParseCalibration("{not json");
  LONGS_EQUAL((int)pp::Status::kInvalidArgument, (int)not_json.status);
  CHECK(not_json.message.find("not valid JSON") != std::string::npos);
}

TEST(CalibrationFile, TheStiffnessMapReadsTheCalibratedCurveAndNeverExtrapolates) {
  const ph::FingerCurves curves = ph::CurvesFromCalibration(Example());
  pp::FingerSummary finger{};
  ph::LevelTables levels;
  levels.pneumatic_kpa = {0, 10, 30};
  ph::Mapped m = ph::MapRequest(finger, levels, curves, {ph::TargetKind::kLevel, 2});
  LONGS_EQUAL((int)pp::Status::kOk, (int)m.status);
  LONGS_EQUAL(1200, m.target);  // 30 kPa on the calibrated curve, not the nominal line (1164)
  CHECK(m.note.find("calibration of PN-1") != std::string::npos);
  m = ph::MapRequest(finger, levels, curves, {ph::TargetKind::kDeformationMm, 4.5});
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)m.status);
  m = ph::MapRequest(finger, levels, curves, {ph::TargetKind::kDeformationMm, 4.5},
                     ph::RangePolicy::kClamp);
  LONGS_EQUAL(4200, m.target);
  CHECK(m.note.find("clamped") != std::string::npos);
  ph::FingerCurves narrow = curves;
  narrow.calibrated.resize(3);  // calibrated up to 30 kPa only
  levels.pneumatic_kpa = {0, 10, 50};
  m = ph::MapRequest(finger, levels, narrow, {ph::TargetKind::kLevel, 2});
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)m.status);
  CHECK(m.error.find("level pressure") != std::string::npos);
}

TEST(CalibrationFile, DeviceFindsCalibrationsByActuatorSerialAndUploadsThemAtomically) {
  const std::string dir = palpa::testing::MakeTempDir("palpa-cal");
  CHECK(ph::SaveCalibration(Example(), ph::CalibrationPath(dir, "PN-1")).ok());
  ph::DeviceOptions options;
  options.calibration_dir = dir;
  auto opened = ph::Device::Open("sim:thesis-5finger", options);
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  ph::Device& d = *opened.value;
  // Found, but the board holds the nominal inverse: the board's curve is followed, and said.
  CHECK(d.calibration_notes()[0].find(dir + "/PN-1.json disagrees") != std::string::npos);
  CHECK(d.calibration_notes()[1].find("no calibration for PN-2") != std::string::npos);
  const ph::Outcome o = d.ApplyCalibration(0, Example());
  CHECK_TEXT(o.ok(), o.message.c_str());
  CHECK(d.calibration_notes()[0].find("calibration of PN-1") != std::string::npos);
  const auto finger = d.ReadFinger(0);
  CHECK(finger.value.compensator == pp::CompensatorKind::kPrandtlIshlinskii);
  LONGS_EQUAL(5, finger.value.inverse_count);
  LONGS_EQUAL(3, d.ReadLine(0).value.correction_count);
  // The chamber model went with the correction, in the same line record: steps are shaped, with
  // the tube's lag (not the one behind the regulator model, 5 ms).
  LONGS_EQUAL(3500, d.ReadLine(0).value.chamber_tau_us);
  LONGS_EQUAL(ph::kShapingOverdrivePa, d.ReadLine(0).value.overdrive_pa);
  LONGS_EQUAL(0, d.ReadLine(0).value.slew_pa_per_s);
  // A chamber model for a line that is not the finger's is refused, naming it.
  ph::CalibrationFile elsewhere = Example();
  elsewhere.chamber_models[0].line = 3;
  const ph::Outcome foreign = d.ApplyCalibration(0, elsewhere);
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)foreign.status);
  CHECK_TEXT(foreign.message.find("a chamber model is for") != std::string::npos,
             foreign.message.c_str());
  // The wrong actuator, and a set the board would refuse: nothing of either is applied.
  ph::Outcome wrong = d.ApplyCalibration(1, Example());
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)wrong.status);
  CHECK(wrong.message.find("actuator 'PN-2'") != std::string::npos);
  // A staged change whose line record the board refuses (a correction that is not monotone)
  // applies nothing, not even its valid finger record.
  ph::CalibrationFile half = Example();
  half.compensator_params = {0, 0.02f, 0, 0.001f};
  half.regulator_corrections[0].points[1] = {90000, 95500, 93000};
  const ph::Outcome refused = d.ApplyCalibration(0, half);
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)refused.status);
  LONGS_EQUAL(6, d.ReadFinger(0).value.param_count);  // the earlier calibration is untouched
  LONGS_EQUAL(50000, d.ReadLine(0).value.correction[1].command_pa);
}

TEST(CalibrationFile, CompensatorsAreNamedWithTheirSize) {
  ph::CalibrationFile c = Example();
  c.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  c.compensator_params.assign(2 + 2 * 16, 1.0f);
  STRCMP_EQUAL("pi(16)", ph::CompensatorLabel(c).c_str());
  c.compensator = pp::CompensatorKind::kAsymmetricPi;
  c.compensator_params.assign(3 + 2 * 8 + 2 * 4, 1.0f);
  c.compensator_params[0] = 8;
  STRCMP_EQUAL("api(8)", ph::CompensatorLabel(c).c_str());
  c.compensator = pp::CompensatorKind::kBranch;
  c.compensator_params.assign(2 + 3 * 12, 1.0f);
  STRCMP_EQUAL("branch(12)", ph::CompensatorLabel(c).c_str());
  c.compensator = pp::CompensatorKind::kNone;
  c.compensator_params.clear();
  STRCMP_EQUAL("none", ph::CompensatorLabel(c).c_str());
}
