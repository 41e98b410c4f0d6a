// Stimulus sets: the level combinations a discrimination study (or the demo) plays, one file
// format for all of them, with the rule that says which fingers hold the "tumour".
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/stiffness_map.h"

namespace palpa::host {

/// A stimulus-set file's cap: 256 stimuli of 8 fingers with long level names fit many times over.
inline constexpr FileLimits kStimulusSetLimits{"stimulus set", 256 * 1024};

enum class StimulusFingers { kPneumatic, kJamming };

/// How a study presents a stimulus: the fingers' values one after another (single-finger), or
/// all at once (multi-finger) — the thesis's two conditions (§5.3.4.1, §5.4.4).
enum class StimulusCondition { kSingleFinger, kMultiFinger };

struct StimulusLevel {
  std::string name;
  double kpa = 0;  ///< pneumatic: pressure; jamming: vacuum (≤ 0), at the set's bias
};

struct Stimulus {
  std::vector<int> levels;  ///< a level index per finger, fingers in their order on the hand
  std::vector<int> tumour;  ///< the fingers (0-based) the rule marks; empty: no tumour
};

struct StimulusSet {
  std::string name, description;
  StimulusFingers fingers_kind = StimulusFingers::kPneumatic;
  int fingers = 0;
  double bias_kpa = 0;                ///< jamming: the pneumatic chamber's bias
  std::vector<StimulusLevel> levels;  ///< softest first: each level stiffer than the one before
  std::vector<StimulusCondition> conditions;
  std::string selected_from;  ///< the set this one was chosen from; empty for a full set
  std::string selection;      ///< how it was chosen
  std::vector<Stimulus> stimuli;
};

/// The thesis's rule: a tumour is one finger, or two adjacent fingers, stiffer than the rest
/// (which are equal); none when all are equal. The marked fingers (0-based), or nullopt when the
/// levels fit none of the three patterns.
std::optional<std::vector<int>> TumourFingers(const std::vector<int>& levels);

/// Every combination of `fingers` fingers over `levels` levels that the rule allows (18 for three
/// fingers at three levels, 9 for two): no tumour first, then by contrast.
std::vector<std::vector<int>> TumourCombinations(size_t fingers, int levels);

/// Parses a stimulus-set document; a bad one is an invalid argument naming the first wrong field by
/// its path (`stimuli[3].tumour: ...`). Every stimulus must follow the rule and say what it gives.
Result<StimulusSet> ParseStimulusSet(const std::string& text);

/// The sets shipped with the library (host/lib/data/stimuli): thesis-pneumatic-18, -14,
/// thesis-jamming-9, -8.
std::vector<std::string> ShippedStimulusSets();
/// A shipped set's file text (empty for an unknown name): to copy and edit into a set of one's own.
std::string ShippedStimulusSetText(const std::string& name);
/// A shipped set by name, or a file by path (anything with a '/' or ending in .json); not_found for
/// an unknown name, else why the file is refused.
Result<StimulusSet> LoadStimulusSet(const std::string& name_or_path);

/// Level tables carrying these sets' levels (a pneumatic set, a jamming set, either may be null),
/// so that a level request plays the set's values; the rest from `base`.
LevelTables LevelTablesFor(const StimulusSet* pneumatic, const StimulusSet* jamming,
                           LevelTables base = LevelTables::Shipped());

std::string LevelNames(const StimulusSet& set, const Stimulus& s);

}  // namespace palpa::host
