// The board's methods: parameters checked, then the device called on the board worker.
#include "palpa/serve/board_methods.h"

#include "palpa/host/bit_names.h"
#include "palpa/host/board_json.h"
#include "palpa/host/config_json.h"
#include "palpa/serve/params.h"

namespace palpa::serve {
namespace {

using Json = rpc::Json;

BoardAnswer Answer(const host::Outcome& o, Json result) {
  if (!o.ok()) return BoardAnswer{nullptr, Refused(o)};
  return BoardAnswer{std::move(result), std::nullopt};
}

BoardAnswer Info(host::Device& d) {
  const auto diag = d.Diagnostics();
  if (!diag.ok()) return Answer(diag.outcome(), nullptr);
  const protocol::HelloReply b = d.info();
  std::vector<host::FingerCurves> curves;
  for (uint8_t f = 0; f < b.finger_count; ++f) curves.push_back(d.curves(f));
  return Answer({},
                Json{{"device", d.link().Describe()},
                     {"board", host::BoardIdentityJson(b, diag.value, d.link().catalog_matches())},
                     {"lines", host::LinesJson(b, 0)},
                     {"fingers", host::FingersJson(b, &curves, 0)},
                     {"numbering", "lines and fingers from 0, as on the wire"}});
}

BoardAnswer Diagnostics(host::Device& d) {
  const auto diag = d.Diagnostics();
  if (!diag.ok()) return Answer(diag.outcome(), nullptr);
  const auto stats = d.LoopStats();
  if (!stats.ok()) return Answer(stats.outcome(), nullptr);
  return Answer({}, host::DiagnosticsJson(diag.value, stats.value, d.link().counters(), 0));
}

BoardAnswer ConfigRead(host::Device& d) {
  const auto config = d.ReadConfig();
  if (!config.ok()) return Answer(config.outcome(), nullptr);
  return Answer({}, host::ConfigToJson(config.value));
}

BoardJob ConfigApply(Json patch, bool save) {
  return [patch = std::move(patch), save](host::Device& d) {
    auto config = d.ReadConfig();
    if (!config.ok()) return Answer(config.outcome(), nullptr);
    try {
      host::ApplyConfigJson(patch, config.value);
    } catch (const std::exception& e) {
      return BoardAnswer{nullptr,
                         BadParam(std::string("config: ") + e.what() + " (nothing was sent)")};
    }
    if (const host::Outcome o = d.ApplyConfig(config.value); !o.ok()) return Answer(o, nullptr);
    if (save) {
      if (const host::Outcome o = d.SaveConfig(); !o.ok()) return Answer(o, nullptr);
    }
    return Answer({}, Json{{"applied", true}, {"saved", save}});
  };
}

Json AppliedJson(const host::Applied& a) {
  Json j = {{"finger", a.finger}, {"raw", a.raw}, {"curves", a.map}};
  if (a.raw) {
    j["setpoints"] = Json::array({{{"line", a.line_a}, {"kpa", a.line_a_pa / 1000.0}}});
    if (a.line_b != protocol::kNoLine)
      j["setpoints"].push_back({{"line", a.line_b}, {"kpa", a.line_b_pa / 1000.0}});
  } else {
    j["target"] = a.target;
    j["unit"] = a.unit;
  }
  if (a.from_table) j["level_kpa"] = a.table_kpa;
  return j;
}

}  // namespace

rpc::Error Refused(const host::Outcome& o) {
  Json data = {{"status", protocol::StatusName(o.status)}};
  if (o.faults != 0) data["faults"] = host::FaultList(o.faults);
  if (!o.notes.empty()) data["notes"] = o.notes;
  return rpc::Error{rpc::kBoardRefused, o.message, std::move(data)};
}

namespace {

PreparedCall Prepare(const std::string& method, const Json& params,
                     const protocol::HelloReply& board) {
  const auto no_params = [&](BoardJob job, bool needs_control, bool urgent = false) {
    if (auto e = OnlyKnown(params, {})) return PreparedCall{e, nullptr};
    return PreparedCall{std::nullopt, std::move(job), needs_control, urgent};
  };
  if (method == "board.info") return no_params(Info, false);
  if (method == "board.diagnostics") return no_params(Diagnostics, false);
  if (method == "board.config.read") return no_params(ConfigRead, false);
  if (method == "board.estop") {  // stopping the board is everyone's right
    return no_params(
        [](host::Device& d) {
          return Answer(d.EStop(), Json{{"estop", true}});
        },
        false, true);
  }
  if (method == "board.release") {
    return no_params(
        [](host::Device& d) {
          return Answer(d.Release(), Json{{"released", true}});
        },
        true, true);
  }
  if (method == "board.clear") {
    return no_params(
        [](host::Device& d) {
          const auto before = d.Diagnostics();
          if (!before.ok()) return Answer(before.outcome(), nullptr);
          return Answer(d.ClearFault(),
                        Json{{"cleared", host::FaultList(before.value.fault_bitmap)}});
        },
        true);
  }
  if (method == "board.config.apply") {
    if (auto e = OnlyKnown(params, {"config", "save"})) return {e, nullptr};
    bool save = false;
    if (auto e = ReadFlag(params, "save", save)) return {e, nullptr};
    const auto config = params.find("config");
    if (config == params.end() || !config->is_object())
      return {BadParam("'config' must be an object, as board.config.read gives it"), nullptr};
    return {std::nullopt, ConfigApply(*config, save)};
  }
  if (method == "board.set") {
    std::vector<host::FingerRequest> targets;
    if (auto e = ReadTargets(params, board, targets)) return {e, nullptr};
    return {std::nullopt, [targets](host::Device& d) {
              std::vector<host::Applied> applied;
              const host::Outcome o = d.Set(targets, true, &applied);
              Json list = Json::array();
              for (const host::Applied& a : applied) list.push_back(AppliedJson(a));
              return Answer(o, Json{{"applied", list}, {"notes", o.notes}});
            }};
  }
  if (method == "board.lines.set") {
    std::vector<std::pair<uint8_t, double>> setpoints;
    if (auto e = ReadSetpoints(params, board, setpoints)) return {e, nullptr};
    return {std::nullopt, [setpoints](host::Device& d) {
              return Answer(d.SetLines(setpoints, true), Json{{"applied", true}});
            }};
  }
  return {rpc::Error{rpc::kMethodNotFound, "method not found: '" + method + "'", nullptr}, nullptr};
}

}  // namespace

MethodGroup BoardMethods(const protocol::HelloReply& board) {
  return MethodGroup{
      "board.",
      {"board.info", "board.diagnostics", "board.config.read", "board.config.apply", "board.set",
       "board.lines.set", "board.estop", "board.clear", "board.release"},
      [board](const std::string& method, const Json& params) {
        return Prepare(method, params, board);
      },
      nullptr,
      nullptr};
}

}  // namespace palpa::serve
