// The calibration file's units: every numeric field of a written file has a declared unit, one
// unit per quantity across the file, docs/calibration.md's table is the code's, and files of
// schema version 1 (written before, in kPa, mm, N/mm and N) still read, converted.
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "example_calibration.h"
#include "file_text.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/calibration_units.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using nlohmann::json;

namespace {

/// Every numeric leaf of a document, by its path with `[]` for array elements, and the unit the
/// schema declares for it ("" when it declares none). Parameters and check figures have units by
/// position and by check.
std::vector<std::pair<std::string, std::string>> NumericFields(const json& file) {
  const pp::FingerKind kind =
      file["kind"] == "jamming" ? pp::FingerKind::kJamming : pp::FingerKind::kPneumatic;
  std::vector<std::pair<std::string, std::string>> out;
  std::function<void(const json&, const std::string&)> walk = [&](const json& j,
                                                                  const std::string& path) {
    if (j.is_object()) {
      for (auto it = j.begin(); it != j.end(); ++it) {
        walk(it.value(), path.empty() ? it.key() : path + "." + it.key());
      }
    } else if (j.is_array()) {
      for (const json& item : j) walk(item, path + "[]");
    } else if (j.is_number()) {
      out.push_back({path, ph::CalibrationFieldUnit(path, kind)});
    }
  };
  json rest = file;
  rest["compensator"].erase("params");
  rest["quality"].erase("checks");
  walk(rest, "");
  std::vector<float> params;
  for (const json& p : file["compensator"]["params"]) params.push_back(p.get<float>());
  const std::string kind_name = file["compensator"]["kind"];
  pp::CompensatorKind compensator = pp::CompensatorKind::kNone;
  for (size_t k = 0; k < static_cast<size_t>(pp::CompensatorKind::kCount); ++k) {
    if (kind_name == pp::EnumNames(pp::CompensatorKind{})[k])
      compensator = static_cast<pp::CompensatorKind>(k);
  }
  const auto units = ph::CompensatorParamUnits(compensator, params, kind);
  for (size_t i = 0; i < params.size(); ++i) {
    out.push_back(
        {"compensator.params[" + std::to_string(i) + "]", i < units.size() ? units[i] : ""});
  }
  for (const json& check : file["quality"].value("checks", json::array())) {
    const std::string name = check["name"];
    for (const char* figure : {"value", "limit"}) {
      out.push_back({"quality.checks[" + name + "]." + figure, ph::CheckUnit(name)});
      CHECK_TEXT(check["unit"] == ph::CheckUnit(name), name.c_str());  // and the file says so
    }
  }
  return out;
}

std::vector<json> WrittenExamples() {
  std::vector<json> files;
  for (const ph::CalibrationFile& c :
       {palpa::testing::ExampleCalibration(), palpa::testing::ExampleJammingCalibration()}) {
    const auto text = ph::SerializeCalibration(c);
    CHECK_TEXT(text.ok(), text.message.c_str());
    files.push_back(json::parse(text.value));
  }
  return files;
}

/// The quantity each unit measures: a quantity with two units in one file is what this schema
/// exists to prevent.
const std::map<std::string, std::string> kQuantity = {{"Pa", "pressure"},
                                                      {"µm", "length"},
                                                      {"µm/s", "speed"},
                                                      {"mN/mm", "stiffness"},
                                                      {"mN", "force"},
                                                      {"mJ", "energy"},
                                                      {"s", "time"},
                                                      {"µm/Pa", "deformation per pressure"},
                                                      {"mN/mm/Pa", "stiffness per pressure"},
                                                      {"1", "ratio"},
                                                      {"count", "count"},
                                                      {"index", "index"},
                                                      {"id", "identity"},
                                                      {"version", "version"}};

}  // namespace

TEST_GROUP(CalibrationSchema){};

TEST(CalibrationSchema, EveryNumericFieldOfAWrittenFileHasADeclaredUnit) {
  std::set<std::string> seen;
  for (const json& file : WrittenExamples()) {
    for (const auto& [path, unit] : NumericFields(file)) {
      CHECK_TEXT(!unit.empty(), ("no unit declared for " + path).c_str());
      CHECK_TEXT(kQuantity.count(unit), ("unit '" + unit + "' of " + path).c_str());
      seen.insert(path);
    }
  }
  // And the table declares nothing the files do not have: every entry is a field a writer writes.
  for (const ph::CalibrationField& f : ph::CalibrationFields()) {
    CHECK_TEXT(seen.count(f.path), (std::string(f.path) + " is in no written file").c_str());
  }
}

TEST(CalibrationSchema, EachQuantityHasOneUnitAcrossTheFile) {
  for (const json& file : WrittenExamples()) {
    std::map<std::string, std::set<std::string>> units;  // quantity → units seen
    for (const auto& [path, unit] : NumericFields(file)) {
      const auto quantity = kQuantity.find(unit);
      CHECK_TEXT(quantity != kQuantity.end(), ("unit '" + unit + "' of " + path).c_str());
      units[quantity->second].insert(unit);
    }
    for (const auto& [quantity, seen] : units) {
      std::string list;
      for (const std::string& u : seen) list += u + " ";
      LONGS_EQUAL_TEXT(1, seen.size(),
                       (file["kind"].get<std::string>() + ": " + quantity + " in " + list).c_str());
    }
    // Deformation and the conditions' lengths are one quantity: the same µm.
    CHECK(units["length"].count("µm"));
  }
}

TEST(CalibrationSchema, TheDocumentedTableIsTheCodesTable) {
  std::string table = "| field | pneumatic | jamming | what |\n|---|---|---|---|\n";
  for (const ph::CalibrationField& f : ph::CalibrationFields()) {
    table += std::string("| `") + f.path + "` | " + f.pneumatic + " | " + f.jamming + " | " +
             f.meaning + " |\n";
  }
  const std::string doc = palpa::testing::FileText(std::string(PALPA_DOCS_DIR) + "/calibration.md");
  const std::string begin = "<!-- calibration-units:begin -->\n",
                    end = "<!-- calibration-units:end -->";
  const size_t b = doc.find(begin), e = doc.find(end);
  CHECK_TEXT(b != std::string::npos && e != std::string::npos, "markers in calibration.md");
  const std::string documented = doc.substr(b + begin.size(), e - b - begin.size());
  STRCMP_EQUAL(table.c_str(), documented.c_str());
}

TEST(CalibrationSchema, Version1FilesAreReadInTheBoardsUnits) {
  // Files as the calibrate command wrote them before version 2 (a quick run of each kind).
  for (const char* name : {"calibration_v1_pneumatic.json", "calibration_v1_jamming.json"}) {
    const std::string text =
        palpa::testing::FileText(std::string(PALPA_TEST_DATA_DIR) + "/" + name);
    const json old = json::parse(text);
    LONGS_EQUAL(1, old["schema_version"].get<int>());
    const auto parsed = ph::ParseCalibration(text);
    CHECK_TEXT(parsed.ok(), (std::string(name) + ": " + parsed.message).c_str());
    const ph::CalibrationFile* c = &parsed.value;
    LONGS_EQUAL(1, c->schema_version);
    // kPa → Pa, mm → µm, N/mm → mN/mm, N → mN; what was in the board's units stays.
    DOUBLES_EQUAL(1000 * old["conditions"]["speed_mm_s"].get<double>(), c->speed_um_s, 1e-9);
    DOUBLES_EQUAL(1000 * old["conditions"]["depth_mm"].get<double>(), c->depth_um, 1e-9);
    LONGS_EQUAL(old["curve"].size(), c->curve.size());
    for (size_t i = 0; i < c->curve.size(); ++i) {
      DOUBLES_EQUAL(1000 * old["curve"][i]["kpa"].get<double>(), c->curve[i].drive_pa, 1e-6);
      DOUBLES_EQUAL(1000 * old["curve"][i]["output"].get<double>(), c->curve[i].output, 1e-6);
    }
    for (size_t i = 0; i < c->static_inverse.size(); ++i) {
      LONGS_EQUAL(old["static_inverse"][i]["output"].get<int>(), c->static_inverse[i].output);
    }
    LONGS_EQUAL(old["compensator"]["params"].size(), c->compensator_params.size());
    DOUBLES_EQUAL(1000 * old["quality"]["residual_rms"].get<double>(), c->quality.residual_rms,
                  1e-9);
    for (size_t i = 0; i < c->quality.checks.size(); ++i) {
      const json& k = old["quality"]["checks"][i];
      const double scale = ph::CheckUnit(k["name"]) == "mN" ? 1000 : 1;
      DOUBLES_EQUAL(scale * k["value"].get<double>(), c->quality.checks[i].value, 1e-9);
    }
    if (c->kind == pp::FingerKind::kJamming) {
      DOUBLES_EQUAL(1000 * old["recommended_bias_kpa"].get<double>(), *c->recommended_bias_pa,
                    1e-9);
      DOUBLES_EQUAL(1000 * old["conditions"]["bias_kpa"].get<double>(), *c->bias_pa, 1e-9);
      for (size_t i = 0; i < c->grid.size(); ++i) {
        const json& g = old["grid"][i];
        DOUBLES_EQUAL(1000 * g["vacuum_kpa"].get<double>(), c->grid[i].vacuum_pa, 1e-9);
        DOUBLES_EQUAL(1000 * g["stiffness_mean"].get<double>(), c->grid[i].stiffness_mean, 1e-9);
        DOUBLES_EQUAL(g["loop_area_mean"].get<double>(), c->grid[i].loop_area_mean, 1e-12);
      }
    } else {
      DOUBLES_EQUAL(old["fits"]["rising"]["slope"].get<double>(), c->rising_fit->slope, 1e-12);
      DOUBLES_EQUAL(1000 * old["fits"]["rising"]["intercept"].get<double>(),
                    c->rising_fit->intercept, 1e-9);
    }
    // Written again, it is a file of the current version that reads back the same.
    const auto written = ph::SerializeCalibration(*c);
    CHECK_TEXT(written.ok(), written.message.c_str());
    CHECK_EQUAL(ph::kCalibrationSchemaVersion,
                json::parse(written.value)["schema_version"].get<int>());
    const auto again = ph::ParseCalibration(written.value);
    CHECK_TEXT(again.ok(), again.message.c_str());
    STRCMP_EQUAL(written.value.c_str(), ph::SerializeCalibration(again.value).value.c_str());
    // The stiffness map reads it as it read the file before: mm or N/mm against kPa.
    const ph::FingerCurves curves = ph::CurvesFromCalibration(*c);
    DOUBLES_EQUAL(old["curve"][1]["kpa"].get<double>(), curves.calibrated[1].first, 1e-9);
    DOUBLES_EQUAL(old["curve"][1]["output"].get<double>(), curves.calibrated[1].second, 1e-9);
  }
  // A version 1 file with a version 2 field is refused, naming it.
  json old = json::parse(palpa::testing::FileText(std::string(PALPA_TEST_DATA_DIR) +
                                                  "/calibration_v1_pneumatic.json"));
  old["conditions"]["speed_um_s"] = 100;
  const auto refused = ph::ParseCalibration(old.dump());
  CHECK_FALSE(refused.ok());
  CHECK_TEXT(refused.message.find("conditions.speed_um_s: unknown field") != std::string::npos,
             refused.message.c_str());
}
