// Study files: the schema read field by field (errors name the field and its line), the values'
// ranges by unit, the tumour rule on the conditions, and the study written back whole.
#include "palpa/host/study_file.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "json_line.h"
#include "number_text.h"
#include "palpa/host/json_check.h"
#include "palpa/host/stimulus_set.h"

namespace palpa::host {

std::string StudyText(const std::string& name);  // study_builtin.cc

namespace {

bool Jamming(const Study& s) { return s.finger_kind == protocol::FingerKind::kJamming; }

/// The values a unit allows for the study's finger kind: [lo, hi].
std::pair<double, double> UnitRange(const Study& s) {
  if (s.unit == "kPa") return Jamming(s) ? std::pair{-100.0, 0.0} : std::pair{0.0, 100.0};
  if (s.unit == "mm") return {0, 10};
  if (s.unit == "N/mm") return {0, 5};
  if (s.unit == "level") return {0, 7};
  return {0, 1};  // normalized
}

double Value(const nlohmann::json& j, const std::string& at, const Study& s) {
  const auto [lo, hi] = UnitRange(s);
  if (!j.is_number()) throw JsonInvalid(at + ": must be a number (" + s.unit + ")");
  const double v = j.get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) {
    throw JsonInvalid(at + ": " + Num(v) + " " + s.unit + " is outside " + Num(lo) + " … " +
                      Num(hi) + " for a " + (Jamming(s) ? "jamming" : "pneumatic") + " finger");
  }
  if (s.unit == "level" && v != std::floor(v))
    throw JsonInvalid(at + ": a level is a whole number");
  if (s.unit == "kPa" && std::fabs(v) > s.cap_kpa) {
    throw JsonInvalid(at + ": " + Num(v) + " kPa is beyond the study's cap_kpa (" + Num(s.cap_kpa) +
                      ")");
  }
  return v;
}

/// The rule on the values' stiffness order: which fingers hold the tumour.
std::vector<int> Rule(const Study& s, const std::vector<double>& values, const std::string& at) {
  std::vector<double> order = values;
  std::sort(order.begin(), order.end());
  order.erase(std::unique(order.begin(), order.end()), order.end());
  std::vector<int> ranks;
  for (double v : values) {
    const int r = static_cast<int>(std::lower_bound(order.begin(), order.end(), v) - order.begin());
    ranks.push_back(LargerIsStiffer(s) ? r : static_cast<int>(order.size()) - 1 - r);
  }
  const auto marked = TumourFingers(ranks);
  if (!marked) {
    throw JsonInvalid(at + ": " + ConditionName(values) +
                      " is neither all equal, one finger stiffer, nor two adjacent fingers "
                      "stiffer than the rest (the tumour rule)");
  }
  return *marked;
}

std::vector<int> FingerList(const JsonObject& o, const char* key, size_t lo, size_t hi,
                            int fingers) {
  const nlohmann::json& list = o.List(key, lo, hi);
  std::vector<int> out;
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_number_integer() || list[i].get<long>() < 1 || list[i].get<long>() > fingers)
      throw JsonInvalid(o.Item(key, i) + ": must be a finger, 1 … " + std::to_string(fingers));
    const int f = static_cast<int>(list[i].get<long>()) - 1;
    if (std::count(out.begin(), out.end(), f)) throw JsonInvalid(o.Item(key, i) + ": twice");
    out.push_back(f);
  }
  return out;
}

void ParseConditions(const JsonObject& doc, Study& s) {
  const nlohmann::json& j = doc.At("conditions");
  if (j.is_string()) {  // a stimulus set, shipped or a file
    if (s.unit != "kPa" && s.unit != "level")
      throw JsonInvalid("conditions: a stimulus set gives kPa or levels, not " + s.unit);
    const auto set = LoadStimulusSet(j.get<std::string>());
    if (!set.ok()) throw JsonInvalid("conditions: " + set.message);
    if (set.value.fingers != s.fingers ||
        Jamming(s) != (set.value.fingers_kind == StimulusFingers::kJamming))
      throw JsonInvalid("conditions: stimulus set " + set.value.name +
                        " is for other fingers than the study's");
    if (Jamming(s) && set.value.bias_kpa != s.bias_kpa)
      throw JsonInvalid("conditions: stimulus set " + set.value.name + " has a bias of " +
                        Num(set.value.bias_kpa) + " kPa, the study " + Num(s.bias_kpa));
    for (const Stimulus& st : set.value.stimuli) {
      StudyCondition c;
      for (int l : st.levels) c.values.push_back(s.unit == "level" ? l : set.value.levels[l].kpa);
      for (double v : c.values) Value(v, "conditions", s);  // the cap
      c.name = ConditionName(c.values);
      c.tumour = st.tumour;
      s.conditions.push_back(c);
    }
    return;
  }
  const nlohmann::json& list = doc.List("conditions", 1, 256);
  std::set<std::vector<double>> seen;
  std::set<std::string> names;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = doc.Item("conditions", i);
    const JsonObject o(list[i], path, {"name", "values", "tumour"});
    StudyCondition c;
    const nlohmann::json& values =
        o.List("values", static_cast<size_t>(s.fingers), static_cast<size_t>(s.fingers));
    for (size_t f = 0; f < values.size(); ++f)
      c.values.push_back(Value(values[f], o.Item("values", f), s));
    c.tumour = Rule(s, c.values, path + ".values");
    if (o.Has("tumour") &&
        FingerList(o, "tumour", 0, static_cast<size_t>(s.fingers), s.fingers) != c.tumour)
      throw JsonInvalid(path + ".tumour: not what the rule gives for " + ConditionName(c.values));
    c.name = o.Has("name") ? o.Text("name") : ConditionName(c.values);
    if (!seen.insert(c.values).second) throw JsonInvalid(path + ".values: a condition twice");
    if (!names.insert(c.name).second) throw JsonInvalid(path + ".name: \"" + c.name + "\" twice");
    s.conditions.push_back(c);
  }
}

Staircase ParseStaircase(const JsonObject& b, const std::string& path, const Study& s) {
  const JsonObject o(b.At("staircase"), path + ".staircase",
                     {"reference", "start", "step", "down", "up", "reversals", "reversals_used",
                      "max_trials", "fingers"});
  Staircase st;
  const auto [lo, hi] = UnitRange(s);
  const double span = hi - lo;
  st.reference = Value(o.At("reference"), path + ".staircase.reference", s);
  st.start = Value(o.At("start"), path + ".staircase.start", s);
  if (LargerIsStiffer(s) ? st.start <= st.reference : st.start >= st.reference)
    throw JsonInvalid(path + ".staircase.start: must be stiffer than the reference");
  st.step = o.Number("step", span * 1e-4, span);
  if (o.Has("down")) st.down = static_cast<int>(o.Integer("down", 1, 5));
  if (o.Has("up")) st.up = static_cast<int>(o.Integer("up", 1, 5));
  if (o.Has("reversals")) st.reversals = static_cast<int>(o.Integer("reversals", 2, 50));
  st.reversals_used = static_cast<int>(o.Integer("reversals_used", 1, st.reversals));
  if (o.Has("max_trials")) st.max_trials = static_cast<int>(o.Integer("max_trials", 4, 500));
  if (o.Has("fingers")) st.fingers = FingerList(o, "fingers", 2, 2, s.fingers);
  return st;
}

StudyBlock ParseBlock(const nlohmann::json& j, const std::string& path, const Study& s) {
  const JsonObject o(j, path,
                     {"name", "kind", "mode", "present_ms", "repetitions", "randomise", "practice",
                      "break_every", "staircase"});
  StudyBlock b;
  b.name = o.Text("name");
  if (o.Has("kind"))
    b.kind = o.Choice("kind", {"detection", "staircase"}) == "staircase" ? BlockKind::kStaircase
                                                                         : BlockKind::kDetection;
  b.mode = o.Choice("mode", {"sequential", "simultaneous"}) == "sequential"
               ? StudyMode::kSequential
               : StudyMode::kSimultaneous;
  if (o.Has("present_ms")) b.present_ms = static_cast<int>(o.Integer("present_ms", 100, 60000));
  if (o.Has("randomise")) b.randomise = o.Flag("randomise");
  if (o.Has("break_every")) b.break_every = static_cast<int>(o.Integer("break_every", 0, 1000));
  if (o.Has("practice")) b.practice = static_cast<int>(o.Integer("practice", 0, 50));
  if (b.kind == BlockKind::kStaircase) {
    if (o.Has("repetitions")) throw JsonInvalid(path + ".repetitions: a staircase adapts instead");
    if (!o.Has("staircase")) throw JsonInvalid(path + ".staircase: missing");
    b.staircase = ParseStaircase(o, path, s);
  } else {
    if (o.Has("staircase")) throw JsonInvalid(path + ".staircase: only a staircase block has one");
    if (s.conditions.empty()) throw JsonInvalid(path + ": a detection block needs conditions");
    if (o.Has("repetitions")) b.repetitions = static_cast<int>(o.Integer("repetitions", 1, 100));
  }
  return b;
}

Study Parse(const nlohmann::json& j) {
  const JsonObject doc(
      j, "",
      {"schema", "schema_version", "name", "description", "question", "finger_kind", "fingers",
       "bias_kpa", "unit", "cap_kpa", "reset", "settle", "conditions", "blocks"});
  if (doc.Text("schema") != "palpa-study") throw JsonInvalid("schema: must be \"palpa-study\"");
  doc.Integer("schema_version", 1, 1);
  Study s;
  s.name = doc.Text("name");
  if (doc.Has("description")) s.description = doc.Text("description");
  if (doc.Has("question")) s.question = doc.Text("question");
  const bool jamming = doc.Choice("finger_kind", {"pneumatic", "jamming"}) == "jamming";
  s.finger_kind = jamming ? protocol::FingerKind::kJamming : protocol::FingerKind::kPneumatic;
  s.fingers = static_cast<int>(doc.Integer("fingers", 1, 8));
  if (jamming) {
    s.bias_kpa = doc.Number("bias_kpa", 0, 20);
  } else if (doc.Has("bias_kpa")) {
    throw JsonInvalid("bias_kpa: only a jamming study has a bias");
  }
  s.unit = doc.Choice("unit", {"kPa", "mm", "N/mm", "level", "normalized"});
  if (s.unit == "mm" && jamming) throw JsonInvalid("unit: a jamming finger renders N/mm, not mm");
  if (s.unit == "N/mm" && !jamming)
    throw JsonInvalid("unit: a pneumatic finger renders mm, not N/mm");
  s.cap_kpa = doc.Number("cap_kpa", 1, 100);
  if (doc.Has("reset")) {
    const JsonObject r(doc.At("reset"), "reset", {"approach", "hold_ms"});
    if (r.Has("approach"))
      s.approach_from_above = r.Choice("approach", {"below", "above"}) == "above";
    if (r.Has("hold_ms")) s.reset_ms = static_cast<int>(r.Integer("hold_ms", 0, 60000));
  }
  if (doc.Has("settle")) {
    const JsonObject t(doc.At("settle"), "settle",
                       {"tolerance_kpa", "band_kpa", "hold_ms", "timeout_ms"});
    if (t.Has("tolerance_kpa")) s.tolerance_kpa = t.Number("tolerance_kpa", 0.05, 20);
    if (t.Has("band_kpa")) s.band_kpa = t.Number("band_kpa", 0.1, 20);
    if (t.Has("hold_ms")) s.hold_ms = static_cast<int>(t.Integer("hold_ms", 10, 5000));
    if (t.Has("timeout_ms"))
      s.settle_timeout_ms = static_cast<int>(t.Integer("timeout_ms", 100, 120000));
  }
  if (doc.Has("conditions")) ParseConditions(doc, s);
  const nlohmann::json& blocks = doc.List("blocks", 1, 16);
  std::set<std::string> names;
  for (size_t i = 0; i < blocks.size(); ++i) {
    const std::string path = doc.Item("blocks", i);
    s.blocks.push_back(ParseBlock(blocks[i], path, s));
    if (!names.insert(s.blocks.back().name).second)
      throw JsonInvalid(path + ".name: \"" + s.blocks.back().name + "\" twice");
  }
  return s;
}

}  // namespace

std::string ConditionName(const std::vector<double>& values) {
  const bool negative = std::any_of(values.begin(), values.end(), [](double v) { return v < 0; });
  std::string out;
  for (double v : values) out += (out.empty() ? "" : negative ? "/" : "-") + Num(v);
  return out;
}

bool LargerIsStiffer(const Study& s) { return !(Jamming(s) && s.unit == "kPa"); }

Request StudyRequest(const Study& s, double value) {
  if (s.unit == "kPa") return {TargetKind::kPressureKpa, value};
  if (s.unit == "mm") return {TargetKind::kDeformationMm, value};
  if (s.unit == "N/mm") return {TargetKind::kStiffnessNPerMm, value};
  if (s.unit == "level") return {TargetKind::kLevel, value};
  return {TargetKind::kNormalized, value};
}

Result<Study> ParseStudy(const std::string& text) {
  Result<Study> r = ParseJsonWith<Study>(text, Parse);
  if (!r.ok()) r.message = WithJsonLine(text, r.message);
  return r;
}

Result<Study> LoadStudy(const std::string& name_or_path) {
  const bool file =
      name_or_path.find('/') != std::string::npos ||
      (name_or_path.size() > 5 && name_or_path.compare(name_or_path.size() - 5, 5, ".json") == 0);
  if (!file) {
    const std::string text = StudyText(name_or_path);
    if (text.empty()) {
      std::string names;
      for (const std::string& n : BuiltInStudies()) names += (names.empty() ? "" : ", ") + n;
      return {Status::kNotFound, "no study \"" + name_or_path + "\" (built in: " + names +
                                     "; a file needs a path or a .json name)"};
    }
    Result<Study> r = ParseStudy(text);
    if (r.ok()) r.value.source = "built in";
    return r;
  }
  Result<Study> r = ReadAndParse(name_or_path, kStudyFileLimits, ParseStudy);
  if (r.ok()) r.value.source = name_or_path;
  return r;
}

}  // namespace palpa::host
