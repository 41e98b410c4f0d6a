// Study definitions and plans: the built-in thesis studies, custom files with every kind of bad
// field named with its line, the resolved study round-tripping, and the seeded trial order.
#include <algorithm>
#include <map>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "palpa/host/study_file.h"
#include "palpa/host/study_plan.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;

namespace {

ph::Study BuiltIn(const char* name) {
  const auto s = ph::LoadStudy(name);
  CHECK_TEXT(s.ok(), s.message.c_str());
  return s.value;
}

const char kCustom[] = R"({
  "schema": "palpa-study", "schema_version": 1, "name": "custom",
  "finger_kind": "pneumatic", "fingers": 3, "unit": "mm", "cap_kpa": 60,
  "conditions": [
    {"values": [0.2, 0.2, 0.2]},
    {"values": [0.2, 1.0, 0.2]},
    {"values": [1.0, 1.0, 0.2], "tumour": [1, 2]}
  ],
  "blocks": [
    {"name": "a", "mode": "simultaneous", "repetitions": 3, "practice": 1, "break_every": 4},
    {"name": "jnd", "kind": "staircase", "mode": "simultaneous",
     "staircase": {"reference": 0.5, "start": 1.0, "step": 0.05, "reversals": 6,
                   "reversals_used": 4, "fingers": [1, 3]}}
  ]
})";

/// The custom study with one value replaced (a JSON pointer), parsed: its error message.
std::string RefusedStudy(const std::string& pointer, const nlohmann::json& value) {
  nlohmann::json j = nlohmann::json::parse(kCustom);
  if (value.is_discarded()) {
    j.erase(pointer.substr(1));
  } else {
    j[nlohmann::json::json_pointer(pointer)] = value;
  }
  const auto s = ph::ParseStudy(j.dump(2));
  CHECK_FALSE_TEXT(s.ok(), ("accepted with " + pointer).c_str());
  return s.message;
}

/// The line the refusal names holds `text` (the field, or its value).
void OnLine(const std::string& pointer, const nlohmann::json& value, const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(kCustom);
  j[nlohmann::json::json_pointer(pointer)] = value;
  const std::string doc = j.dump(2);
  const std::string message = ph::ParseStudy(doc).message;
  CHECK_TEXT(message.compare(0, 5, "line ") == 0, message.c_str());
  const int line = std::stoi(message.substr(5));
  size_t at = 0;
  for (int i = 1; i < line; ++i) at = doc.find('\n', at) + 1;
  const std::string named = doc.substr(at, doc.find('\n', at) - at);
  CHECK_TEXT(named.find(text) != std::string::npos, (message + "\n  line: " + named).c_str());
}

void Contains(const std::string& text, const std::string& part) {
  CHECK_TEXT(text.find(part) != std::string::npos, (text + "\n  lacks: " + part).c_str());
}

}  // namespace

TEST_GROUP(StudyFile){};

TEST(StudyFile, ThePneumaticStudyIsTheThesisOne) {
  const ph::Study s = BuiltIn("thesis-pneumatic");
  LONGS_EQUAL(3, s.fingers);
  LONGS_EQUAL(14, s.conditions.size());
  std::set<double> levels;
  for (const ph::StudyCondition& c : s.conditions) {
    levels.insert(c.values.begin(), c.values.end());
    // The rule: no tumour exactly when all are equal; else the marked fingers are the highest.
    const double hi = *std::max_element(c.values.begin(), c.values.end());
    const bool equal = std::count(c.values.begin(), c.values.end(), hi) == 3;
    CHECK_EQUAL(equal, c.tumour.empty());
    for (int f : c.tumour) DOUBLES_EQUAL(hi, c.values[f], 0);
    CHECK(c.tumour.size() <= 2);
    if (c.tumour.size() == 2) LONGS_EQUAL(c.tumour[0] + 1, c.tumour[1]);
  }
  CHECK(levels == (std::set<double>{0, 10, 30}));
  LONGS_EQUAL(2, s.blocks.size());
  STRCMP_EQUAL("single-finger", s.blocks[0].name.c_str());
  CHECK(s.blocks[0].mode == ph::StudyMode::kSequential);
  STRCMP_EQUAL("three-finger", s.blocks[1].name.c_str());
  CHECK(s.blocks[1].mode == ph::StudyMode::kSimultaneous);
}

TEST(StudyFile, TheJammingStudyIsTheThesisOne) {
  const ph::Study s = BuiltIn("thesis-jamming");
  LONGS_EQUAL(2, s.fingers);
  DOUBLES_EQUAL(20, s.bias_kpa, 0);
  LONGS_EQUAL(8, s.conditions.size());
  CHECK_FALSE(ph::LargerIsStiffer(s));
  for (const ph::StudyCondition& c : s.conditions) {
    const double stiffest = *std::min_element(c.values.begin(), c.values.end());  // deepest
    CHECK_EQUAL(c.values[0] == c.values[1], c.tumour.empty());
    for (int f : c.tumour) DOUBLES_EQUAL(stiffest, c.values[f], 0);
    for (double v : c.values) CHECK(v == 0 || v == -10 || v == -100);
  }
  STRCMP_EQUAL("0/-100", ph::ConditionName({0, -100}).c_str());
}

TEST(StudyFile, ACustomStudyRoundTripsWithItsDefaultsFilledIn) {
  const auto s = ph::ParseStudy(kCustom);
  CHECK_TEXT(s.ok(), s.message.c_str());
  LONGS_EQUAL(3, s.value.conditions.size());
  STRCMP_EQUAL("0.2-1-0.2", s.value.conditions[1].name.c_str());
  CHECK((std::vector<int>{1}) == s.value.conditions[1].tumour);
  const ph::Staircase& st = s.value.blocks[1].staircase;
  LONGS_EQUAL(2, st.down);
  LONGS_EQUAL(1, st.up);
  CHECK((std::vector<int>{0, 2}) == st.fingers);
  const nlohmann::ordered_json j = ph::StudyToJson(s.value);
  const auto again = ph::ParseStudy(j.dump(2));
  CHECK_TEXT(again.ok(), again.message.c_str());
  STRCMP_EQUAL(j.dump().c_str(), ph::StudyToJson(again.value).dump().c_str());
  // Built-ins too, through their stimulus sets' conditions.
  for (const std::string& name : ph::BuiltInStudies()) {
    const nlohmann::ordered_json b = ph::StudyToJson(BuiltIn(name.c_str()));
    const auto back = ph::ParseStudy(b.dump());
    CHECK_TEXT(back.ok(), back.message.c_str());
    STRCMP_EQUAL(b.dump().c_str(), ph::StudyToJson(back.value).dump().c_str());
  }
}

TEST(StudyFile, BadFieldsAreNamedWithTheirLine) {
  Contains(RefusedStudy("/blocks/0/repetitions", 0), "blocks[0].repetitions");
  OnLine("/blocks/0/repetitions", 0, "\"repetitions\": 0");
  OnLine("/conditions/1/values/1", 200, "200");
  OnLine("/blocks/1/staircase/step", -1, "\"step\": -1");
  Contains(RefusedStudy("/conditions/1/values/1", 200), "conditions[1].values[1]: 200 mm");
  Contains(RefusedStudy("/conditions/1/values", {0.2, 1.0, 0.5}), "the tumour rule");
  Contains(RefusedStudy("/conditions/2/tumour", {1}),
           "conditions[2].tumour: not what the rule gives");
  Contains(RefusedStudy("/conditions/2", {{"values", {0.2, 0.2, 0.2}}}),
           "conditions[2].values: a condition twice");
  Contains(RefusedStudy("/unit", "N/mm"), "unit: a pneumatic finger renders mm");
  Contains(RefusedStudy("/unit", "furlong"), "unit");
  Contains(RefusedStudy("/blocks/0/mode", "sideways"), "blocks[0].mode");
  Contains(RefusedStudy("/blocks/1/staircase/start", 0.4),
           "blocks[1].staircase.start: must be stiffer");
  Contains(RefusedStudy("/blocks/1/staircase/reversals_used", 7),
           "blocks[1].staircase.reversals_used");
  Contains(RefusedStudy("/blocks/1/staircase/fingers", {1, 4}), "blocks[1].staircase.fingers[1]");
  Contains(RefusedStudy("/blocks/1/name", "a"), "blocks[1].name: \"a\" twice");
  Contains(RefusedStudy("/blocks/0/colour", "red"), "colour");
  Contains(RefusedStudy("/schema", "palpa-stimuli"), "schema");
  Contains(RefusedStudy("/fingers", 9), "fingers");
  Contains(RefusedStudy("/cap_kpa", nlohmann::json::value_t::discarded), "cap_kpa");
  // The cap, on values that are pressures.
  nlohmann::json j = nlohmann::json::parse(kCustom);
  j["unit"] = "kPa";
  j["cap_kpa"] = 20;
  j["conditions"] = {{{"values", {0, 30, 0}}}};
  j["blocks"].erase(1);
  const auto capped = ph::ParseStudy(j.dump(2));
  CHECK_FALSE(capped.ok());
  Contains(capped.message, "conditions[0].values[1]: 30 kPa is beyond the study's cap_kpa (20)");
  // A stimulus set for other fingers.
  j["cap_kpa"] = 100;
  j["conditions"] = "thesis-jamming-8";
  Contains(ph::ParseStudy(j.dump()).message, "thesis-jamming-8 is for other fingers");
  const auto syntax = ph::ParseStudy("{\n\"schema\": \"palpa-study\",\n}");
  Contains(syntax.message, "line 3");
  const auto unknown = ph::LoadStudy("thesis-pneumatics");
  Contains(unknown.message, "built in: thesis-pneumatic, thesis-jamming");
}

TEST_GROUP(StudyPlan){};

TEST(StudyPlan, ASeededOrderWithPracticeFirstAndBreaks) {
  const ph::Study s = BuiltIn("thesis-pneumatic");
  const uint64_t seed = ph::StudySeed(s, "P01");
  CHECK(seed < (uint64_t{1} << 53));
  CHECK(seed != ph::StudySeed(s, "P02"));
  const ph::StudyPlan plan = ph::PlanStudy(s, seed);
  LONGS_EQUAL(2 * (2 + 14), plan.trials.size());
  for (size_t b = 0; b < 2; ++b) {
    std::map<int, int> count;
    for (size_t i = 0; i < 16; ++i) {
      const ph::ScheduledTrial& t = plan.trials[b * 16 + i];
      LONGS_EQUAL(b * 16 + i, t.index);
      LONGS_EQUAL(b, t.block);
      CHECK_EQUAL(i < 2, t.practice);
      if (!t.practice) ++count[t.condition];
      // A break at the start of the second block and after every 7 scored trials.
      CHECK_EQUAL((i == 0 && b == 1) || i == 9, t.break_before);
    }
    LONGS_EQUAL(14, count.size());  // every condition once
  }
  // The same seed gives the same order; another participant another.
  const ph::StudyPlan again = ph::PlanStudy(s, seed);
  const ph::StudyPlan other = ph::PlanStudy(s, ph::StudySeed(s, "P02"));
  bool same = true, differs = false;
  for (size_t i = 0; i < plan.trials.size(); ++i) {
    same = same && again.trials[i].condition == plan.trials[i].condition;
    differs = differs || other.trials[i].condition != plan.trials[i].condition;
  }
  CHECK(same);
  CHECK(differs);
  const nlohmann::ordered_json order = ph::PlanToJson(s, plan);
  STRCMP_EQUAL("single-finger", order[0]["block"].get<std::string>().c_str());
  STRCMP_EQUAL(s.conditions[plan.trials[5].condition].name.c_str(),
               order[5]["condition"].get<std::string>().c_str());
}

TEST(StudyPlan, UnrandomisedBlocksKeepTheConditionsOrder) {
  auto s = ph::ParseStudy(kCustom);
  CHECK_TEXT(s.ok(), s.message.c_str());
  s.value.blocks[0].randomise = false;
  const ph::StudyPlan plan = ph::PlanStudy(s.value, 7);
  // 1 practice, 3 × 3 conditions in order, then the staircase's max_trials.
  LONGS_EQUAL(1 + 9 + 60, plan.trials.size());
  for (int i = 0; i < 9; ++i) LONGS_EQUAL(i % 3, plan.trials[1 + i].condition);
  CHECK(plan.trials[5].break_before);  // after 4 scored
  LONGS_EQUAL(-1, plan.trials[10].condition);
  bool both_sides[2] = {false, false};
  for (size_t i = 10; i < plan.trials.size(); ++i)
    both_sides[plan.trials[i].comparison_second] = true;
  CHECK(both_sides[0] && both_sides[1]);
}
