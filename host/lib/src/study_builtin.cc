// The thesis's two studies (§5.3.4.1, §5.4.4) as study files, and any study written back whole.
#include "palpa/host/study_file.h"

namespace palpa::host {

namespace {

struct BuiltIn {
  const char* name;
  const char* text;
};

// The thesis gives the levels, the rule, the number of conditions and the two modes; the rest is
// palpa's choice and says so: which 14 and 8 conditions (the stimulus sets), one repetition of
// each per block (168 = 14 × 12 trials per mode over 12 participants), two practice trials, a
// break half-way, 3 s per finger in the sequential block.
const BuiltIn kBuiltIn[] = {
    {"thesis-pneumatic", R"({
  "schema": "palpa-study", "schema_version": 1,
  "name": "thesis-pneumatic",
  "description": "Three pneumatic fingers at 0, 10 and 30 kPa, the thesis's 14 conditions (stimulus set thesis-pneumatic-14), each finger in turn and then all three at once.",
  "question": "Is there a tumour? If so, under which fingers?",
  "finger_kind": "pneumatic", "fingers": 3, "unit": "kPa", "cap_kpa": 40,
  "conditions": "thesis-pneumatic-14",
  "blocks": [
    {"name": "single-finger", "mode": "sequential", "present_ms": 3000, "practice": 2, "break_every": 7},
    {"name": "three-finger", "mode": "simultaneous", "practice": 2, "break_every": 7}
  ]
})"},
    {"thesis-jamming", R"({
  "schema": "palpa-study", "schema_version": 1,
  "name": "thesis-jamming",
  "description": "Two jamming fingers at 0, -10 and -100 kPa with the air cushion at 20 kPa, the thesis's 8 conditions (stimulus set thesis-jamming-8), each finger in turn and then both at once.",
  "question": "Is there a tumour? If so, under which finger?",
  "finger_kind": "jamming", "fingers": 2, "bias_kpa": 20, "unit": "kPa", "cap_kpa": 100,
  "conditions": "thesis-jamming-8",
  "settle": {"timeout_ms": 15000},
  "blocks": [
    {"name": "single-finger", "mode": "sequential", "present_ms": 3000, "practice": 2, "break_every": 4},
    {"name": "two-finger", "mode": "simultaneous", "practice": 2, "break_every": 4}
  ]
})"},
};

}  // namespace

std::string StudyText(const std::string& name) {
  for (const BuiltIn& b : kBuiltIn) {
    if (name == b.name) return b.text;
  }
  return "";
}

std::vector<std::string> BuiltInStudies() {
  std::vector<std::string> names;
  for (const BuiltIn& b : kBuiltIn) names.push_back(b.name);
  return names;
}

nlohmann::ordered_json StudyToJson(const Study& s) {
  const bool jamming = s.finger_kind == protocol::FingerKind::kJamming;
  nlohmann::ordered_json j = {{"schema", "palpa-study"}, {"schema_version", 1}, {"name", s.name}};
  if (!s.description.empty()) j["description"] = s.description;
  j["question"] = s.question;
  j["finger_kind"] = jamming ? "jamming" : "pneumatic";
  j["fingers"] = s.fingers;
  if (jamming) j["bias_kpa"] = s.bias_kpa;
  j["unit"] = s.unit;
  j["cap_kpa"] = s.cap_kpa;
  j["reset"] = {{"approach", s.approach_from_above ? "above" : "below"}, {"hold_ms", s.reset_ms}};
  j["settle"] = {{"tolerance_kpa", s.tolerance_kpa},
                 {"band_kpa", s.band_kpa},
                 {"hold_ms", s.hold_ms},
                 {"timeout_ms", s.settle_timeout_ms}};
  nlohmann::ordered_json conditions = nlohmann::ordered_json::array();
  for (const StudyCondition& c : s.conditions) {
    nlohmann::ordered_json tumour = nlohmann::ordered_json::array();
    for (int f : c.tumour) tumour.push_back(f + 1);
    conditions.push_back({{"name", c.name}, {"values", c.values}, {"tumour", tumour}});
  }
  if (!s.conditions.empty()) j["conditions"] = conditions;
  nlohmann::ordered_json blocks = nlohmann::ordered_json::array();
  for (const StudyBlock& b : s.blocks) {
    nlohmann::ordered_json o = {
        {"name", b.name},
        {"kind", b.kind == BlockKind::kStaircase ? "staircase" : "detection"},
        {"mode", b.mode == StudyMode::kSequential ? "sequential" : "simultaneous"},
        {"present_ms", b.present_ms}};
    if (b.kind == BlockKind::kDetection) o["repetitions"] = b.repetitions;
    o["randomise"] = b.randomise;
    o["practice"] = b.practice;
    o["break_every"] = b.break_every;
    if (b.kind == BlockKind::kStaircase) {
      const Staircase& st = b.staircase;
      o["staircase"] = {{"reference", st.reference},
                        {"start", st.start},
                        {"step", st.step},
                        {"down", st.down},
                        {"up", st.up},
                        {"reversals", st.reversals},
                        {"reversals_used", st.reversals_used},
                        {"max_trials", st.max_trials},
                        {"fingers", {st.fingers[0] + 1, st.fingers[1] + 1}}};
    }
    blocks.push_back(o);
  }
  j["blocks"] = blocks;
  return j;
}

}  // namespace palpa::host
