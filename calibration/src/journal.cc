// Calibration journals read back: every field the protocol uses checked and named.
#include <cstdint>
#include <limits>

#include "palpa/calibration/calibration_protocol.h"
#include "palpa/host/json_check.h"
#include "palpa/protocol/enums.h"

namespace palpa::calibration {
namespace {

using host::JsonInvalid;
using host::JsonObject;
using nlohmann::json;

/// A list of at most `most` items, each an array of `width` finite numbers (integers where
/// `integers` says, within int32 where `int32` says): sweep samples, correction points, presses.
void CheckRows(const json& list, const std::string& path, size_t most, size_t width,
               uint32_t integers, bool int32) {
  if (!list.is_array()) throw JsonInvalid(path + ": must be an array");
  if (list.size() > most)
    throw JsonInvalid(path + ": has " + std::to_string(list.size()) + " entries, at most " +
                      std::to_string(most));
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string row = path + "[" + std::to_string(i) + "]";
    if (!list[i].is_array() || list[i].size() != width)
      throw JsonInvalid(row + ": must be an array of " + std::to_string(width) + " numbers");
    for (size_t k = 0; k < width; ++k) {
      const json& v = list[i][k];
      const std::string where = row + "[" + std::to_string(k) + "]";
      const bool integer = (integers >> k & 1u) != 0;
      if (integer ? !v.is_number_integer() : !v.is_number())
        throw JsonInvalid(where + (integer ? ": must be an integer" : ": must be a number"));
      const double d = v.get<double>();
      if (int32 &&
          (d < std::numeric_limits<int32_t>::min() || d > std::numeric_limits<int32_t>::max())) {
        throw JsonInvalid(where + ": does not fit 32 bits");
      }
      if (integer && v.is_number_integer() && !int32 && (d < 0 || d > 1e9))
        throw JsonInvalid(where + ": is outside 0 … 1e9");
    }
  }
}

void CheckJournal(const json& state) {
  JsonObject o(state, "", {"rig_time_s", "corrections", "map", "sweep", "chamber"});
  if (o.Has("rig_time_s")) o.Number("rig_time_s", 0, 1e9);
  if (o.Has("corrections")) {
    const json& corrections = o.At("corrections");
    if (!corrections.is_object()) throw JsonInvalid("corrections: must be an object");
    for (auto it = corrections.begin(); it != corrections.end(); ++it) {
      const std::string where = "corrections." + it.key();
      const std::string& key = it.key();
      if (key.size() != 1 || key[0] < '0' || key[0] >= '0' + protocol::kMaxLines)
        throw JsonInvalid(where + ": not a line (0 … " + std::to_string(protocol::kMaxLines - 1) +
                          ")");
      CheckRows(it.value(), where, 64, 3, 0b111, true);
    }
  }
  if (o.Has("map")) {
    JsonObject map(o.At("map"), "map", {"grid_done", "presses"});
    if (map.Has("grid_done")) map.Integer("grid_done", 0, 100000);
    // A press: bias, vacuum, measured bias, measured vacuum, stiffness, loop area, r², residual,
    // free force, readings (an integer), time.
    if (map.Has("presses")) CheckRows(map.At("presses"), "map.presses", 100000, 11, 1u << 9, false);
  }
  if (o.Has("sweep")) CheckRows(o.At("sweep"), "sweep", 100000, 2, 0, false);
  // The chamber's fit (dead time, regulator and chamber lags, residual, the tube's lag and its
  // residual), or none identified.
  if (o.Has("chamber")) CheckRows(o.At("chamber"), "chamber", 1, 6, 0, false);
}

}  // namespace

host::Result<json> ParseJournal(const std::string& text) {
  auto state = host::ParseJson(text);
  if (!state.ok()) return state;
  try {
    CheckJournal(state.value);
  } catch (const std::exception& e) {  // JsonInvalid names the field
    return {host::Status::kInvalidArgument, e.what()};
  }
  return state;
}

host::Result<json> LoadJournal(const std::string& path) {
  return host::ReadAndParse(path, kJournalLimits, ParseJournal);
}

}  // namespace palpa::calibration
