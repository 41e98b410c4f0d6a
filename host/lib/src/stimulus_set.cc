// Stimulus-set files: parsing with the failing field named, the tumour rule, the shipped sets.
#include "palpa/host/stimulus_set.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>

#include "number_text.h"
#include "palpa/host/json_check.h"

namespace palpa::host {
namespace {

struct Shipped {
  const char* name;
  const char* text;
};

const Shipped kShipped[] = {
#include "stimuli_json.inc"
};

std::string Fingers(const std::vector<int>& zero_based) {
  std::string s = "[";
  for (size_t i = 0; i < zero_based.size(); ++i)
    s += (i ? ", " : "") + std::to_string(zero_based[i] + 1);
  return s + "]";
}

std::vector<StimulusLevel> ParseLevels(const JsonObject& doc, bool jamming) {
  const nlohmann::json& list = doc.List("levels", 2, 8);
  std::vector<StimulusLevel> levels;
  std::set<std::string> names;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = doc.Item("levels", i);
    const JsonObject o(list[i], path, {"name", "kpa"});
    StimulusLevel l{o.Text("name"), jamming ? o.Number("kpa", -100, 0) : o.Number("kpa", 0, 100)};
    if (!names.insert(l.name).second) throw JsonInvalid(path + ".name: \"" + l.name + "\" twice");
    if (!levels.empty() && (jamming ? l.kpa >= levels.back().kpa : l.kpa <= levels.back().kpa)) {
      throw JsonInvalid(path + ".kpa: " + Num(l.kpa) + " is not stiffer than the level before (" +
                        Num(levels.back().kpa) + "): levels go softest first, " +
                        (jamming ? "vacuum deepening" : "pressure rising"));
    }
    levels.push_back(l);
  }
  return levels;
}

Stimulus ParseStimulus(const nlohmann::json& j, const std::string& path, const StimulusSet& set) {
  const JsonObject o(j, path, {"levels", "tumour"});
  Stimulus s;
  const nlohmann::json& names =
      o.List("levels", static_cast<size_t>(set.fingers), static_cast<size_t>(set.fingers));
  for (size_t f = 0; f < names.size(); ++f) {
    const std::string at = o.Item("levels", f);
    if (!names[f].is_string()) throw JsonInvalid(at + ": must be a level's name");
    const std::string name = names[f].get<std::string>();
    const auto it = std::find_if(set.levels.begin(), set.levels.end(),
                                 [&](const StimulusLevel& l) { return l.name == name; });
    if (it == set.levels.end())
      throw JsonInvalid(at + ": \"" + name + "\" is not a level of this set");
    s.levels.push_back(static_cast<int>(it - set.levels.begin()));
  }
  const std::optional<std::vector<int>> rule = TumourFingers(s.levels);
  if (!rule) {
    throw JsonInvalid(path + ".levels: " + LevelNames(set, s) +
                      " is neither all equal, one finger stiffer, nor two adjacent fingers "
                      "stiffer than the rest (the tumour rule)");
  }
  const nlohmann::json& marked = o.List("tumour", 0, static_cast<size_t>(set.fingers));
  for (size_t i = 0; i < marked.size(); ++i) {
    if (!marked[i].is_number_integer() || marked[i].get<long>() < 1 ||
        marked[i].get<long>() > set.fingers) {
      throw JsonInvalid(o.Item("tumour", i) + ": must be a finger, 1 … " +
                        std::to_string(set.fingers));
    }
    s.tumour.push_back(static_cast<int>(marked[i].get<long>()) - 1);
  }
  if (s.tumour != *rule) {
    throw JsonInvalid(path + ".tumour: " + Fingers(s.tumour) + " is not what the rule gives for " +
                      LevelNames(set, s) + ": " + Fingers(*rule));
  }
  return s;
}

StimulusSet Parse(const nlohmann::json& j) {
  const JsonObject doc(j, "",
                       {"schema", "schema_version", "name", "description", "finger_kind", "fingers",
                        "bias_kpa", "levels", "rule", "conditions", "selection", "stimuli"});
  if (doc.Text("schema") != "palpa-stimuli") throw JsonInvalid("schema: must be \"palpa-stimuli\"");
  doc.Integer("schema_version", 1, 1);
  StimulusSet set;
  set.name = doc.Text("name");
  set.description = doc.Text("description");
  const bool jamming = doc.Choice("finger_kind", {"pneumatic", "jamming"}) == "jamming";
  set.fingers_kind = jamming ? StimulusFingers::kJamming : StimulusFingers::kPneumatic;
  set.fingers = static_cast<int>(doc.Integer("fingers", 1, 8));
  if (jamming) {
    set.bias_kpa = doc.Number("bias_kpa", 0, 20);
  } else if (doc.Has("bias_kpa")) {
    throw JsonInvalid("bias_kpa: only a jamming set has a bias");
  }
  set.levels = ParseLevels(doc, jamming);
  doc.Choice("rule", {"tumour"});
  const nlohmann::json& conditions = doc.List("conditions", 1, 2);
  for (size_t i = 0; i < conditions.size(); ++i) {
    const std::string at = doc.Item("conditions", i);
    const std::string c = conditions[i].is_string() ? conditions[i].get<std::string>() : "";
    if (c != "single-finger" && c != "multi-finger")
      throw JsonInvalid(at + ": must be \"single-finger\" or \"multi-finger\"");
    const StimulusCondition k =
        c == "single-finger" ? StimulusCondition::kSingleFinger : StimulusCondition::kMultiFinger;
    if (std::count(set.conditions.begin(), set.conditions.end(), k))
      throw JsonInvalid(at + ": \"" + c + "\" twice");
    set.conditions.push_back(k);
  }
  const JsonObject selection(doc.At("selection"), "selection", {"from", "how"});
  if (selection.Has("from")) set.selected_from = selection.Text("from");
  set.selection = selection.Text("how");
  const nlohmann::json& stimuli = doc.List("stimuli", 1, 256);
  std::map<std::vector<int>, size_t> seen;
  for (size_t i = 0; i < stimuli.size(); ++i) {
    const std::string path = doc.Item("stimuli", i);
    Stimulus s = ParseStimulus(stimuli[i], path, set);
    const auto [it, fresh] = seen.emplace(s.levels, i);
    if (!fresh) {
      throw JsonInvalid(path + ".levels: the same as stimuli[" + std::to_string(it->second) +
                        "] (" + LevelNames(set, s) + ")");
    }
    set.stimuli.push_back(std::move(s));
  }
  return set;
}

}  // namespace

std::optional<std::vector<int>> TumourFingers(const std::vector<int>& levels) {
  if (levels.empty()) return std::nullopt;
  const auto [lo, hi] = std::minmax_element(levels.begin(), levels.end());
  std::vector<int> marked;
  for (size_t f = 0; f < levels.size(); ++f) {
    if (levels[f] == *hi && *hi != *lo) {
      marked.push_back(static_cast<int>(f));
    } else if (levels[f] != *lo) {
      return std::nullopt;  // a third level
    }
  }
  if (marked.size() <= 1) return marked;
  // Two adjacent fingers, with a rest that is softer.
  if (marked.size() == 2 && marked[1] == marked[0] + 1 && levels.size() > 2) return marked;
  return std::nullopt;
}

std::vector<std::vector<int>> TumourCombinations(size_t fingers, int levels) {
  std::vector<std::vector<int>> out;
  for (int level = 0; level < levels; ++level)
    out.push_back(std::vector<int>(fingers, level));  // no tumour
  for (int low = 0; low < levels; ++low) {
    for (int high = low + 1; high < levels; ++high) {
      for (size_t at = 0; at < fingers; ++at) {  // one finger stiffer
        std::vector<int> c(fingers, low);
        c[at] = high;
        out.push_back(c);
      }
      for (size_t at = 0; at + 1 < fingers && fingers > 2; ++at) {  // two adjacent, with a rest
        std::vector<int> c(fingers, low);
        c[at] = c[at + 1] = high;
        out.push_back(c);
      }
    }
  }
  return out;
}

Result<StimulusSet> ParseStimulusSet(const std::string& text) {
  return ParseJsonWith<StimulusSet>(text, Parse);
}

std::vector<std::string> ShippedStimulusSets() {
  std::vector<std::string> names;
  for (const Shipped& s : kShipped) names.push_back(s.name);
  return names;
}

std::string ShippedStimulusSetText(const std::string& name) {
  for (const Shipped& s : kShipped) {
    if (name == s.name) return s.text;
  }
  return "";
}

Result<StimulusSet> LoadStimulusSet(const std::string& name_or_path) {
  const bool file =
      name_or_path.find('/') != std::string::npos ||
      (name_or_path.size() > 5 && name_or_path.compare(name_or_path.size() - 5, 5, ".json") == 0);
  if (!file) {
    for (const Shipped& s : kShipped) {
      if (name_or_path == s.name) {
        auto set = ParseStimulusSet(s.text);
        if (!set.ok()) set.message = name_or_path + ": " + set.message;
        return set;
      }
    }
    std::string names;
    for (const Shipped& s : kShipped) names += (names.empty() ? "" : ", ") + std::string(s.name);
    return {Status::kNotFound, "no stimulus set \"" + name_or_path + "\" (shipped: " + names +
                                   "; a file needs a path or a .json name)"};
  }
  return ReadAndParse(name_or_path, kStimulusSetLimits, ParseStimulusSet);
}

LevelTables LevelTablesFor(const StimulusSet* pneumatic, const StimulusSet* jamming,
                           LevelTables base) {
  if (pneumatic != nullptr) {
    base.pneumatic_kpa.clear();
    for (const StimulusLevel& l : pneumatic->levels) base.pneumatic_kpa.push_back(l.kpa);
  }
  if (jamming != nullptr) {
    base.jamming_kpa.clear();
    for (const StimulusLevel& l : jamming->levels) base.jamming_kpa.push_back(l.kpa);
    base.jamming_bias_kpa = jamming->bias_kpa;
  }
  return base;
}

std::string LevelNames(const StimulusSet& set, const Stimulus& s) {
  std::string out;
  for (int l : s.levels) {
    out += (out.empty() ? "" : " ") +
           (l >= 0 && static_cast<size_t>(l) < set.levels.size() ? set.levels[l].name : "?");
  }
  return out;
}

}  // namespace palpa::host
