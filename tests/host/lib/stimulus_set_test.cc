// Stimulus sets: the shipped thesis sets against the tumour rule, the subsets' stated choice,
// and every kind of bad file refused with the field named.
#include <algorithm>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/stimulus_set.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;

namespace {

ph::StimulusSet Shipped(const char* name) {
  const auto set = ph::LoadStimulusSet(name);
  CHECK_TEXT(set.ok(), set.message.c_str());
  return set.value;
}

std::vector<std::vector<int>> Levels(const ph::StimulusSet& set) {
  std::vector<std::vector<int>> out;
  for (const ph::Stimulus& s : set.stimuli) out.push_back(s.levels);
  return out;
}

/// A valid small set to break one field at a time.
nlohmann::json Valid() {
  return nlohmann::json::parse(R"({
    "schema": "palpa-stimuli", "schema_version": 1, "name": "t", "description": "d",
    "finger_kind": "pneumatic", "fingers": 3,
    "levels": [{"name": "L0", "kpa": 0}, {"name": "L1", "kpa": 10}],
    "rule": "tumour", "conditions": ["multi-finger"],
    "selection": {"from": null, "how": "by hand"},
    "stimuli": [{"levels": ["L0", "L0", "L0"], "tumour": []},
                {"levels": ["L0", "L1", "L0"], "tumour": [2]},
                {"levels": ["L1", "L1", "L0"], "tumour": [1, 2]}]})");
}

std::string RefusedStimuli(const nlohmann::json& j) {
  const auto set = ph::ParseStimulusSet(j.dump());
  CHECK_TEXT(!set.ok(), "accepted");
  LONGS_EQUAL((int)palpa::protocol::Status::kInvalidArgument, (int)set.status);
  return set.message;
}

#define CHECK_REFUSED(json, starts)                                                  \
  do {                                                                               \
    const std::string e = RefusedStimuli(json);                                      \
    CHECK_TEXT(e.rfind(starts, 0) == 0, (std::string(starts) + " <> " + e).c_str()); \
  } while (0)

}  // namespace

TEST_GROUP(StimulusSets){};

TEST(StimulusSets, TheRuleMarksOneOrTwoAdjacentStifferFingers) {
  CHECK(ph::TumourFingers({1, 1, 1}) == std::vector<int>{});
  CHECK(ph::TumourFingers({0, 2, 0}) == std::vector<int>{1});
  CHECK(ph::TumourFingers({2, 2, 0}) == (std::vector<int>{0, 1}));
  CHECK(ph::TumourFingers({0, 1}) == std::vector<int>{1});
  CHECK(!ph::TumourFingers({2, 0, 2}).has_value());  // not adjacent
  CHECK(!ph::TumourFingers({0, 1, 2}).has_value());  // three levels
  CHECK(ph::TumourFingers({1, 1}) == std::vector<int>{});
  LONGS_EQUAL(18, ph::TumourCombinations(3, 3).size());
  LONGS_EQUAL(9, ph::TumourCombinations(2, 3).size());
}

TEST(StimulusSets, TheFullSetsAreEveryCombinationTheRuleAllows) {
  const ph::StimulusSet p = Shipped("thesis-pneumatic-18"), j = Shipped("thesis-jamming-9");
  CHECK(Levels(p) == ph::TumourCombinations(3, 3));
  CHECK(Levels(j) == ph::TumourCombinations(2, 3));
  CHECK(p.selected_from.empty() && j.selected_from.empty());
  DOUBLES_EQUAL(30, p.levels[2].kpa, 0);
  DOUBLES_EQUAL(-100, j.levels[2].kpa, 0);
  DOUBLES_EQUAL(20, j.bias_kpa, 0);
  LONGS_EQUAL(2, p.conditions.size());
}

TEST(StimulusSets, TheSubsetsHaveTheThesisSizesAndTheirStatedChoice) {
  const ph::StimulusSet p14 = Shipped("thesis-pneumatic-14"), j8 = Shipped("thesis-jamming-8");
  LONGS_EQUAL(14, p14.stimuli.size());
  LONGS_EQUAL(8, j8.stimuli.size());
  STRCMP_EQUAL("thesis-pneumatic-18", p14.selected_from.c_str());
  STRCMP_EQUAL("thesis-jamming-9", j8.selected_from.c_str());
  const auto full_p = ph::TumourCombinations(3, 3), full_j = ph::TumourCombinations(2, 3);
  const auto in_p14 = Levels(p14), in_j8 = Levels(j8);
  // The 14: every no-tumour and one-finger stimulus; two adjacent fingers only 30 over 0 kPa.
  for (const auto& c : full_p) {
    const auto marked = *ph::TumourFingers(c);
    const bool strong_pair = marked.size() == 2 && *std::min_element(c.begin(), c.end()) == 0 &&
                             *std::max_element(c.begin(), c.end()) == 2;
    const bool in = std::count(in_p14.begin(), in_p14.end(), c) > 0;
    CHECK(in == (marked.size() < 2 || strong_pair));
  }
  // The 8: all but both fingers at the middle level.
  for (const auto& c : full_j) {
    const bool in = std::count(in_j8.begin(), in_j8.end(), c) > 0;
    CHECK(in == (c != std::vector<int>{1, 1}));
  }
}

TEST(StimulusSets, ShippedNamesFilesAndUnknownNames) {
  const auto names = ph::ShippedStimulusSets();
  LONGS_EQUAL(4, names.size());
  auto set = ph::LoadStimulusSet("thesis-pneumatic-15");
  LONGS_EQUAL((int)palpa::protocol::Status::kNotFound, (int)set.status);
  CHECK(set.message.find("thesis-pneumatic-14") != std::string::npos);  // lists what there is
  set = ph::LoadStimulusSet("/nonexistent/set.json");
  LONGS_EQUAL((int)palpa::protocol::Status::kNotFound, (int)set.status);
  CHECK(set.message.find("cannot be read") != std::string::npos);
}

TEST(StimulusSets, EveryBadFieldIsNamed) {
  CHECK(ph::ParseStimulusSet(Valid().dump()).ok());
  const auto broken = ph::ParseStimulusSet("{");
  CHECK_FALSE(broken.ok());
  CHECK_TEXT(broken.message.rfind("not valid JSON", 0) == 0, broken.message.c_str());
  nlohmann::json j = Valid();
  j["colour"] = 1;
  CHECK_REFUSED(j, "colour: unknown field");
  j = Valid();
  j["schema"] = "palpa-calibration";
  CHECK_REFUSED(j, "schema:");
  j = Valid();
  j["schema_version"] = 2;
  CHECK_REFUSED(j, "schema_version:");
  j = Valid();
  j["fingers"] = 9;
  CHECK_REFUSED(j, "fingers:");
  j = Valid();
  j["bias_kpa"] = 20;
  CHECK_REFUSED(j, "bias_kpa: only a jamming set");
  j = Valid();
  j["finger_kind"] = "jamming";
  CHECK_REFUSED(j, "bias_kpa: missing");
  j = Valid();
  j["levels"][1]["kpa"] = 0;
  CHECK_REFUSED(j, "levels[1].kpa:");
  j = Valid();
  j["levels"][1]["name"] = "L0";
  CHECK_REFUSED(j, "levels[1].name:");
  j = Valid();
  j["levels"][0]["kpa"] = 150;
  CHECK_REFUSED(j, "levels[0].kpa:");
  j = Valid();
  j["rule"] = "majority";
  CHECK_REFUSED(j, "rule:");
  j = Valid();
  j["conditions"] = {"multi-finger", "multi-finger"};
  CHECK_REFUSED(j, "conditions[1]:");
  j = Valid();
  j["conditions"] = {"blind"};
  CHECK_REFUSED(j, "conditions[0]:");
  j = Valid();
  j["selection"].erase("how");
  CHECK_REFUSED(j, "selection.how: missing");
  j = Valid();
  j["stimuli"][1]["levels"][1] = "L5";
  CHECK_REFUSED(j, "stimuli[1].levels[1]: \"L5\" is not a level");
  j = Valid();
  j["stimuli"][1]["levels"] = {"L0", "L1"};
  CHECK_REFUSED(j, "stimuli[1].levels:");
  j = Valid();
  j["stimuli"][2]["levels"] = {"L1", "L0", "L1"};
  CHECK_REFUSED(j, "stimuli[2].levels: L1 L0 L1 is neither");
  j = Valid();
  j["stimuli"][1]["tumour"] = {1};
  CHECK_REFUSED(j, "stimuli[1].tumour: [1] is not what the rule gives for L0 L1 L0: [2]");
  j = Valid();
  j["stimuli"][1]["tumour"] = {4};
  CHECK_REFUSED(j, "stimuli[1].tumour[0]:");
  j = Valid();
  j["stimuli"][2] = j["stimuli"][1];
  CHECK_REFUSED(j, "stimuli[2].levels: the same as stimuli[1]");
  j = Valid();
  j["stimuli"] = nlohmann::json::array();
  CHECK_REFUSED(j, "stimuli:");
}

TEST(StimulusSets, LevelTablesCarryTheSetsLevels) {
  const ph::StimulusSet p = Shipped("thesis-pneumatic-14"), j = Shipped("thesis-jamming-8");
  const ph::LevelTables t = ph::LevelTablesFor(&p, &j);
  CHECK(t.pneumatic_kpa == (std::vector<double>{0, 10, 30}));
  CHECK(t.jamming_kpa == (std::vector<double>{0, -10, -100}));
  DOUBLES_EQUAL(20, t.jamming_bias_kpa, 0);
  const ph::LevelTables only = ph::LevelTablesFor(nullptr, nullptr);
  CHECK(only.pneumatic_kpa == ph::LevelTables::Shipped().pneumatic_kpa);
}
