// Named parameters, checked before anything is sent.
#include "palpa/serve/params.h"

#include <cmath>

#include "palpa/host/request_text.h"

namespace palpa::serve {

rpc::Error BadParam(const std::string& why) {
  return rpc::Error{
      rpc::kInvalidParams, "invalid params: " + why, {{"status", "invalid_argument"}}};
}

std::optional<rpc::Error> OnlyKnown(const rpc::Json& params,
                                    std::initializer_list<const char*> known) {
  for (const auto& [key, value] : params.items()) {
    (void)value;
    bool found = false;
    std::string names;
    for (const char* k : known) {
      found = found || key == k;
      names += (names.empty() ? "" : ", ") + std::string(k);
    }
    if (!found)
      return BadParam(
          "unknown parameter '" + key + "' (" +
          (names.empty() ? std::string("this method takes none") : "expected " + names) + ")");
  }
  return std::nullopt;
}

std::optional<rpc::Error> ReadInteger(const rpc::Json& value, const std::string& name, int64_t min,
                                      int64_t max, int64_t& out) {
  const std::string range = " from " + std::to_string(min) + " to " + std::to_string(max);
  if (!value.is_number_integer()) {
    return BadParam("'" + name + "' must be an integer" + range + ", not " +
                    (value.is_number() ? "the number " + value.dump() : value.type_name()));
  }
  const bool negative = value.is_number_integer() && !value.is_number_unsigned();
  if (negative ? value.get<int64_t>() < min || value.get<int64_t>() > max
               : value.get<uint64_t>() > static_cast<uint64_t>(max) ||
                     static_cast<int64_t>(value.get<uint64_t>()) < min) {
    return BadParam("'" + name + "' is " + value.dump() + ", outside" + range);
  }
  out = negative ? value.get<int64_t>() : static_cast<int64_t>(value.get<uint64_t>());
  return std::nullopt;
}

std::optional<rpc::Error> ReadNumber(const rpc::Json& value, const std::string& name, double min,
                                     double max, double& out) {
  if (!value.is_number())
    return BadParam("'" + name + "' must be a number, not " + value.type_name());
  const double v = value.get<double>();
  if (!std::isfinite(v) || v < min || v > max) {
    return BadParam("'" + name + "' is " + value.dump() + ", outside " + std::to_string(min) +
                    " … " + std::to_string(max));
  }
  out = v;
  return std::nullopt;
}

std::optional<rpc::Error> ReadFlag(const rpc::Json& params, const char* name, bool& out) {
  out = false;
  const auto at = params.find(name);
  if (at == params.end()) return std::nullopt;
  if (!at->is_boolean()) return BadParam(std::string("'") + name + "' must be true or false");
  out = at->get<bool>();
  return std::nullopt;
}

namespace {

/// The list under `key`: an array of objects, 1 to `most` of them.
std::optional<rpc::Error> ReadList(const rpc::Json& params, const char* key, size_t most,
                                   const rpc::Json*& out) {
  if (auto e = OnlyKnown(params, {key})) return e;
  const auto at = params.find(key);
  if (at == params.end() || !at->is_array() || at->empty() || at->size() > most) {
    return BadParam(std::string("'") + key + "' must be a list of 1 to " + std::to_string(most) +
                    " objects");
  }
  for (const rpc::Json& entry : *at) {
    if (!entry.is_object())
      return BadParam(std::string("each of '") + key + "' must be an object, not " +
                      entry.type_name());
  }
  out = &*at;
  return std::nullopt;
}

/// The unit members a target may carry, and what each becomes.
struct UnitName {
  const char* name;
  host::TargetKind kind;
};
constexpr UnitName kUnits[] = {{"level", host::TargetKind::kLevel},
                               {"normalized", host::TargetKind::kNormalized},
                               {"n_per_mm", host::TargetKind::kStiffnessNPerMm},
                               {"mm", host::TargetKind::kDeformationMm},
                               {"kpa", host::TargetKind::kPressureKpa}};

}  // namespace

std::optional<rpc::Error> ReadTargets(const rpc::Json& params, const protocol::HelloReply& board,
                                      std::vector<host::FingerRequest>& out) {
  const rpc::Json* list = nullptr;
  if (auto e = ReadList(params, "targets", board.finger_count, list)) return e;
  for (size_t i = 0; i < list->size(); ++i) {
    const rpc::Json& entry = (*list)[i];
    const std::string where = "targets[" + std::to_string(i) + "]";
    if (auto e =
            OnlyKnown(entry, {"finger", "level", "normalized", "n_per_mm", "mm", "kpa", "value"}))
      return BadParam(where + ": " + e->message.substr(16));
    int64_t finger = 0;
    if (!entry.contains("finger")) return BadParam(where + ": 'finger' is missing");
    if (auto e = ReadInteger(entry["finger"], where + ".finger", 0, board.finger_count - 1, finger))
      return e;
    for (const host::FingerRequest& before : out) {
      if (before.finger == finger)
        return BadParam(where + ": finger " + std::to_string(finger) + " is given twice");
    }
    host::FingerRequest request;
    request.finger = static_cast<uint8_t>(finger);
    int units = 0;
    for (const UnitName& u : kUnits) {
      const auto at = entry.find(u.name);
      if (at == entry.end()) continue;
      ++units;
      double v = 0;
      const std::string name = where + "." + u.name;
      if (u.kind == host::TargetKind::kLevel) {
        int64_t level = 0;
        if (auto e = ReadInteger(*at, name, 0, 255, level)) return e;
        v = static_cast<double>(level);
      } else if (auto e = ReadNumber(*at, name, -1e6, 1e6, v)) {
        return e;
      }
      request.request = host::Request{u.kind, v};
    }
    if (const auto at = entry.find("value"); at != entry.end()) {
      ++units;
      if (!at->is_string() || at->get_ref<const std::string&>().size() > 64)
        return BadParam(where + ".value must be a string such as \"L2\", \"0.5\" or \"0.9N/mm\"");
      const host::Result<host::Request> r = host::ParseRequestText(at->get<std::string>());
      if (!r.ok()) return BadParam(where + ".value '" + at->get<std::string>() + "': " + r.message);
      request.request = r.value;
    }
    if (units != 1) {
      return BadParam(where +
                      ": give exactly one of level, normalized, n_per_mm, mm, kpa or value");
    }
    out.push_back(request);
  }
  return std::nullopt;
}

std::optional<rpc::Error> ReadSetpoints(const rpc::Json& params, const protocol::HelloReply& board,
                                        std::vector<std::pair<uint8_t, double>>& out) {
  const rpc::Json* list = nullptr;
  if (auto e = ReadList(params, "setpoints", board.line_count, list)) return e;
  for (size_t i = 0; i < list->size(); ++i) {
    const rpc::Json& entry = (*list)[i];
    const std::string where = "setpoints[" + std::to_string(i) + "]";
    if (auto e = OnlyKnown(entry, {"line", "kpa"}))
      return BadParam(where + ": " + e->message.substr(16));
    if (!entry.contains("line") || !entry.contains("kpa"))
      return BadParam(where + ": expected {\"line\": N, \"kpa\": VALUE}");
    int64_t line = 0;
    double kpa = 0;
    if (auto e = ReadInteger(entry["line"], where + ".line", 0, board.line_count - 1, line))
      return e;
    if (auto e = ReadNumber(entry["kpa"], where + ".kpa", -1000, 1000, kpa)) return e;
    for (const auto& before : out) {
      if (before.first == line)
        return BadParam(where + ": line " + std::to_string(line) + " is given twice");
    }
    out.emplace_back(static_cast<uint8_t>(line), kpa);
  }
  return std::nullopt;
}

}  // namespace palpa::serve
