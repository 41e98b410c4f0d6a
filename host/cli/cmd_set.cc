// palpa set, palpa line: fingers in people's terms, raw line setpoints.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "cli.h"
#include "palpa/host/board_json.h"
#include "palpa/host/field_text.h"

namespace palpa::cli {

host::Result<double> TakeHold(std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] != "--hold") continue;
    const host::Result<std::string> value = OptionValue(args, i);
    if (!value.ok()) return value.outcome();
    double hold_s = 0;
    if (!ParseNumber(value.value, hold_s) || hold_s < 0) {
      return {protocol::Status::kInvalidArgument,
              "--hold " + value.value + ": a number of seconds (0 or more)"};
    }
    args.erase(args.begin() + static_cast<long>(i), args.begin() + static_cast<long>(i) + 2);
    return hold_s;
  }
  return 0.0;
}

void Hold(const Context& c, double hold_s) {
  if (hold_s <= 0) {
    if (!c.json) {
      std::printf(
          "note: the fingers return to safe now, as palpa exits and closes its session;\n"
          "      --hold SECONDS keeps them there that long (Ctrl-C ends it early).\n");
    }
    return;
  }
  if (!c.json) {
    std::printf("holding for %g s (Ctrl-C ends it early); the fingers return to safe then\n",
                hold_s);
    std::fflush(stdout);
  }
  const PollsInterruption polls;
  for (double t = 0; t < hold_s && !Interrupted(); t += 0.05)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
}

namespace {

/// Any finger or line number that fits the wire; each board's own range is checked once open.
constexpr uint8_t kAnyNumber = 255;

const char* KindName(host::TargetKind kind) {
  switch (kind) {
    case host::TargetKind::kLevel:
      return "level";
    case host::TargetKind::kNormalized:
      return "normalized";
    case host::TargetKind::kStiffnessNPerMm:
      return "N/mm";
    case host::TargetKind::kDeformationMm:
      return "mm";
    case host::TargetKind::kPressureKpa:
      return "kPa";
  }
  return "";
}

/// "L2", "0.5", "0.9 N/mm": the request as it was given.
std::string RequestText(const host::Request& r) {
  char text[48];
  if (r.kind == host::TargetKind::kLevel) {
    std::snprintf(text, sizeof(text), "level %g", r.value);
  } else if (r.kind == host::TargetKind::kNormalized) {
    std::snprintf(text, sizeof(text), "%g (of 0..1)", r.value);
  } else {
    std::snprintf(text, sizeof(text), "%g %s", r.value, KindName(r.kind));
  }
  return text;
}

nlohmann::ordered_json AppliedJson(const host::Applied& a) {
  nlohmann::ordered_json j = {
      {"finger", a.finger + 1},
      {"request", {{"kind", KindName(a.request.kind)}, {"value", a.request.value}}},
      {"mode", a.raw ? "raw" : "target"}};
  if (a.from_table) j["level_kpa"] = a.table_kpa;
  if (a.raw) {
    nlohmann::ordered_json setpoints = {{{"line", a.line_a + 1}, {"kpa", a.line_a_pa / 1000.0}}};
    if (a.line_b != protocol::kNoLine)
      setpoints.push_back({{"line", a.line_b + 1}, {"kpa", a.line_b_pa / 1000.0}});
    j["setpoints"] = setpoints;
  } else {
    j["target"] = {{"value", a.target}, {"unit", a.unit}};
  }
  j["map"] = a.map;
  return j;
}

/// One line per finger: what was asked and the value the board now follows or holds.
void PrintApplied(const host::Applied& a) {
  std::string value;
  char text[96];
  if (a.from_table) {
    std::snprintf(text, sizeof(text), " = %g kPa", a.table_kpa);
    value += text;
  }
  if (a.raw) {
    std::snprintf(text, sizeof(text), " → line %u at %.1f kPa", a.line_a + 1, a.line_a_pa / 1000.0);
    value += text;
    if (a.line_b != protocol::kNoLine) {
      std::snprintf(text, sizeof(text), ", line %u at %.1f kPa", a.line_b + 1,
                    a.line_b_pa / 1000.0);
      value += text;
    }
    value += " (raw, no compensation)";
  } else if (a.target == 0) {
    value += " → target 0 (off: vented or released)";
  } else {
    std::snprintf(text, sizeof(text), " → target %.3f %s", a.target, a.unit);
    value += text;
  }
  std::printf("finger %u: %s%s\n", a.finger + 1u, RequestText(a.request).c_str(), value.c_str());
  if (!a.raw) std::printf("          through %s\n", a.map.c_str());
}

/// The board's range for every finger or line named, once it is open: a usage error otherwise.
int CheckRange(const std::string& command, host::Device& d, const std::vector<uint8_t>& indices,
               bool fingers) {
  const protocol::HelloReply b = d.info();
  const host::Outcome on_board =
      CheckOnBoard(indices, fingers ? b.finger_count : b.line_count, fingers ? "finger" : "line",
                   host::FieldText(b.config_name));
  if (!on_board.ok()) return Usage(command, on_board.message + " (nothing was sent)");
  return kExitOk;
}

}  // namespace

int CmdSet(Context& c, const std::vector<std::string>& given) {
  std::vector<std::string> args = given;
  const host::Result<double> hold = TakeHold(args);
  if (!hold.ok()) return Usage("set", hold.message);
  const double hold_s = hold.value;
  const auto strict = std::find(args.begin(), args.end(), "--strict-calibration");
  if (strict != args.end()) {
    c.options.invalid_calibration_is_error = true;
    args.erase(strict);
  }
  if (args.empty())
    return Usage("set", "expected at least one F=VALUE, e.g. palpa set 1=L2 4=0.9N/mm");
  std::vector<host::FingerRequest> requests;
  std::vector<uint8_t> fingers;
  for (const std::string& a : args) {  // syntax first: a malformed line sends nothing
    const host::Result<host::FingerRequest> r = ParseFingerArgument(a, kAnyNumber);
    if (!r.ok()) return Usage("set", r.message);
    requests.push_back(r.value);
    fingers.push_back(r.value.finger);
  }
  if (const host::Outcome o = CheckDistinct(fingers, args, "finger"); !o.ok())
    return Usage("set", o.message);
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  if (const int rc = CheckRange("set", *d, fingers, true); rc != kExitOk) return rc;
  std::vector<host::Applied> applied;
  const host::Outcome o = d->Set(requests, true, &applied);
  if (!o.ok()) return Fail("set", o.status, o.message);
  WarnCurves(*d);
  if (c.json) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const host::Applied& a : applied) list.push_back(AppliedJson(a));
    nlohmann::ordered_json out = {{"applied", list}, {"hold_s", hold_s}};
    if (!d->curve_warnings().empty())
      out["curve_warnings"] = host::CurveWarningsJson(d->curve_warnings(), 1);
    PrintJson(out);
  } else {
    for (const host::Applied& a : applied) PrintApplied(a);
  }
  Hold(c, hold_s);
  return kExitOk;
}

int CmdLine(Context& c, const std::vector<std::string>& given) {
  std::vector<std::string> args = given;
  const host::Result<double> hold = TakeHold(args);
  if (!hold.ok()) return Usage("line", hold.message);
  const double hold_s = hold.value;
  if (args.empty())
    return Usage("line", "expected at least one L=VALUE in kPa, e.g. palpa line 1=30 6=-40");
  std::vector<std::pair<uint8_t, double>> setpoints;
  std::vector<uint8_t> lines;
  for (const std::string& a : args) {
    const host::Result<std::pair<uint8_t, double>> s = ParseLineArgument(a, kAnyNumber);
    if (!s.ok()) return Usage("line", s.message);
    setpoints.push_back(s.value);
    lines.push_back(s.value.first);
  }
  if (const host::Outcome o = CheckDistinct(lines, args, "line"); !o.ok())
    return Usage("line", o.message);
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  if (const int rc = CheckRange("line", *d, lines, false); rc != kExitOk) return rc;
  const int rc = Report(c, d->SetLines(setpoints), "line");
  if (rc != kExitOk) return rc;
  if (c.json) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const auto& [line, kpa] : setpoints) list.push_back({{"line", line + 1}, {"kpa", kpa}});
    PrintJson({{"applied", list}, {"hold_s", hold_s}});
  } else {
    for (const auto& [line, kpa] : setpoints)
      std::printf("line %u → %g kPa (raw; its finger in raw mode)\n", line + 1u, kpa);
  }
  Hold(c, hold_s);
  return rc;
}

const Command kSetCommand{
    "set", "set F=VALUE ... [--hold S] [--strict-calibration]",
    "Fingers (numbered from 1): L2 (level), 0.5 (0..1), 1.2mm (pneumatic), 0.9N/mm (jamming),\n"
    "-10kPa (raw pressure or vacuum). Units are checked per finger kind. Example on\n"
    "thesis-5finger: palpa set 1=L2 2=0.5 3=1.2mm 4=0.9N/mm 5=-10kPa\n"
    "Requests go through the curve the board holds (each finger's static inverse). A finger\n"
    "whose calibration file cannot be used, or disagrees with the board's curve by more than\n"
    "its fit residual, keeps the board's curve and the reason is printed; --strict-calibration\n"
    "makes that an error (nothing sent). The fingers return to safe as palpa exits and closes\n"
    "its session; --hold S keeps them actuated S seconds first (Ctrl-C, SIGTERM or SIGHUP end\n"
    "the hold early).",
    CmdSet};

const Command kLineCommand{
    "line", "line L=VALUE ... [--hold S]",
    "Raw setpoints in kPa for lines (numbered from 1): palpa line 1=30 6=-40\n"
    "The lines return to safe as palpa exits and closes its session; --hold S keeps them\n"
    "there S seconds first (Ctrl-C, SIGTERM or SIGHUP end the hold early).",
    CmdLine};

}  // namespace palpa::cli
