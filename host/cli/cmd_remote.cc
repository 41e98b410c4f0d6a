// --device serve:HOST:PORT: info, diag, set, line, monitor, estop and clear through a running
// palpa serve, so several programs watch one board while one controls it (docs/serve.md).
#include <chrono>
#include <cstdio>
#include <regex>
#include <thread>

#include "cli.h"
#include "palpa/host/served_device.h"

namespace palpa::cli {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

/// The server numbers fingers and lines from 0, as programs do; the command line from 1, in its
/// output and in the messages it passes on ("finger 0 does not exist" reads "finger 1 ...").
std::string FromOne(const std::string& text) {
  static const std::regex numbered(R"(\b(fingers?|lines?) (\d+)(?: to (\d+))?)");
  std::string out;
  auto at = text.cbegin();
  for (std::sregex_iterator it(text.begin(), text.end(), numbered), end; it != end; ++it) {
    const std::smatch& m = *it;
    out.append(at, m[0].first);
    out += m[1].str() + " " + std::to_string(std::stoul(m[2].str()) + 1);
    if (m[3].matched) out += " to " + std::to_string(std::stoul(m[3].str()) + 1);
    at = m[0].second;
  }
  return out.append(at, text.cend());
}

/// Each "line", "finger", "line_a", "line_b" in `j` (a number) from 1.
json NumberedFromOne(json j) {
  if (j.is_array()) {
    for (json& e : j) e = NumberedFromOne(std::move(e));
  } else if (j.is_object()) {
    for (auto& [key, value] : j.items()) {
      if ((key == "line" || key == "finger" || key == "line_a" || key == "line_b") &&
          value.is_number_unsigned()) {
        value = value.get<uint64_t>() + 1;
      } else if (value.is_string()) {
        value = FromOne(value.get<std::string>());
      } else {
        value = NumberedFromOne(std::move(value));
      }
    }
  }
  if (j.contains("numbering")) j["numbering"] = "lines and fingers from 1, as the command line";
  return j;
}

int Refused(const std::string& what, const host::Outcome& o) {
  return Fail(what, o.status, FromOne(o.message),
              o.status == protocol::Status::kIoError ? kExitConnect : kExitFailed);
}

/// Every finger or line named exists on the served board (a usage error otherwise, nothing sent).
int CheckOnServedBoard(host::ServedDevice& s, const std::string& what,
                       const std::vector<uint8_t>& indices, bool fingers) {
  const size_t count = s.board()[fingers ? "fingers" : "lines"].size();
  const host::Outcome on_board =
      CheckOnBoard(indices, static_cast<uint8_t>(count), fingers ? "finger" : "line",
                   s.board()["board"].value("configuration", ""));
  if (!on_board.ok()) return Usage(what, on_board.message + " (nothing was sent)");
  return kExitOk;
}

/// Takes control: refused (busy) while another client of the server holds it.
int TakeControl(host::ServedDevice& s, const std::string& what) {
  const host::Outcome taken = s.TakeControl();
  return taken.ok() ? kExitOk : Refused(what, taken);
}

int Info(host::ServedDevice& s, const Context& c) {
  const json j = NumberedFromOne(s.board());
  if (c.json) {
    PrintJson(ordered_json::parse(j.dump()));
    return kExitOk;
  }
  const json& b = j["board"];
  std::printf("board           %s, %s, firmware %s (through palpa serve at %s: %s)\n",
              b.value("configuration", "").c_str(), b.value("kind", "").c_str(),
              b.value("firmware", "").c_str(), c.device_uri.c_str(), j.value("device", "").c_str());
  for (const json& l : j["lines"]) {
    std::printf("line %-10s %s, %g … %g kPa\n", l["line"].dump().c_str(),
                l.value("kind", "").c_str(), l.value("limit_min_pa", 0.0) / 1000,
                l.value("limit_max_pa", 0.0) / 1000);
  }
  for (const json& f : j["fingers"]) {
    std::printf("finger %-8s %-9s line %s (%s)\n", f["finger"].dump().c_str(),
                f.value("kind", "").c_str(), f["line_a"].dump().c_str(),
                f.value("unit", "").c_str());
  }
  return kExitOk;
}

int Diag(host::ServedDevice& s, const Context& c) {
  const auto diag = s.client().Call("board.diagnostics");
  if (!diag.ok()) return Refused("diag", diag.outcome());
  const json j = NumberedFromOne(diag.value);
  if (c.json) {
    PrintJson(ordered_json::parse(j.dump()));
    return kExitOk;
  }
  std::printf("reset cause     %s (boot %s), up %.1f s\n", j.value("reset_cause", "").c_str(),
              j["boot_count"].dump().c_str(), j.value("uptime_us", 0.0) / 1e6);
  std::printf("faults latched  %s\n", j["faults_latched_names"].dump().c_str());
  std::printf("faults active   %s\n", j["faults_active_names"].dump().c_str());
  std::printf("loop            %s\n", j["loop"].dump().c_str());
  std::printf("link            %s\n", j["link"].dump().c_str());
  return kExitOk;
}

int Set(host::ServedDevice& s, Context& c, std::vector<std::string> args) {
  const host::Result<double> hold = TakeHold(args);
  if (!hold.ok()) return Usage("set", hold.message);
  if (args.empty()) return Usage("set", "expected at least one F=VALUE, e.g. palpa set 1=L2");
  json targets = json::array();
  std::vector<uint8_t> fingers;
  for (const std::string& a : args) {
    const host::Result<host::FingerRequest> r = ParseFingerArgument(a, 255);
    if (!r.ok()) return Usage("set", r.message);
    fingers.push_back(r.value.finger);
    targets.push_back({{"finger", r.value.finger}, {"value", a.substr(a.find('=') + 1)}});
  }
  if (const host::Outcome o = CheckDistinct(fingers, args, "finger"); !o.ok())
    return Usage("set", o.message);
  if (const int rc = CheckOnServedBoard(s, "set", fingers, true); rc != kExitOk) return rc;
  if (const int rc = TakeControl(s, "set"); rc != kExitOk) return rc;
  const auto applied = s.client().Call("board.set", {{"targets", targets}});
  if (!applied.ok()) return Refused("set", applied.outcome());
  const json j = NumberedFromOne(applied.value);
  if (c.json) {
    PrintJson(ordered_json{{"applied", ordered_json::parse(j["applied"].dump())},
                           {"hold_s", hold.value}});
  } else {
    for (const json& a : j["applied"]) {
      std::printf("finger %s: target %s %s\n", a["finger"].dump().c_str(),
                  a.contains("target") ? a["target"].dump().c_str() : "(raw)",
                  a.value("unit", "").c_str());
    }
  }
  Hold(c, hold.value);  // then control given up: the server releases the board
  return kExitOk;
}

int Line(host::ServedDevice& s, Context& c, std::vector<std::string> args) {
  const host::Result<double> hold = TakeHold(args);
  if (!hold.ok()) return Usage("line", hold.message);
  if (args.empty()) return Usage("line", "expected at least one L=VALUE in kPa");
  json setpoints = json::array();
  std::vector<uint8_t> lines;
  for (const std::string& a : args) {
    const auto l = ParseLineArgument(a, 255);
    if (!l.ok()) return Usage("line", l.message);
    lines.push_back(l.value.first);
    setpoints.push_back({{"line", l.value.first}, {"kpa", l.value.second}});
  }
  if (const host::Outcome o = CheckDistinct(lines, args, "line"); !o.ok())
    return Usage("line", o.message);
  if (const int rc = CheckOnServedBoard(s, "line", lines, false); rc != kExitOk) return rc;
  if (const int rc = TakeControl(s, "line"); rc != kExitOk) return rc;
  const auto applied = s.client().Call("board.lines.set", {{"setpoints", setpoints}});
  if (!applied.ok()) return Refused("line", applied.outcome());
  if (c.json) PrintJson({{"applied", NumberedFromOne(setpoints)}, {"hold_s", hold.value}});
  Hold(c, hold.value);
  return kExitOk;
}

/// Telemetry through the server: a line per update (--json: a JSON line per sample).
int Monitor(host::ServedDevice& served, const Context& c, const std::vector<std::string>& args) {
  host::ServeClient& s = served.client();
  double duration_s = 0, rate = 10;
  for (size_t i = 0; i < args.size(); i += 2) {
    const auto value = OptionValue(args, i);
    double v = 0;
    if ((args[i] != "--duration" && args[i] != "--rate") || !value.ok() ||
        !ParseNumber(value.value, v) || v <= 0 || (args[i] == "--rate" && v > 1000)) {
      return Usage("monitor", "through palpa serve: [--duration S] [--rate HZ] (1 … 1000), not '" +
                                  args[i] + "'");
    }
    (args[i] == "--duration" ? duration_s : rate) = v;
  }
  const auto sub = s.Call("telemetry.subscribe",
                          {{"updates_per_s", std::min(rate, 30.0)}, {"sample_rate_hz", rate}});
  if (!sub.ok()) return Refused("monitor", sub.outcome());
  const PollsInterruption polls;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration_s);
  while (!Interrupted() && (duration_s == 0 || std::chrono::steady_clock::now() < end)) {
    json n;
    if (!s.NextNotification(n, 0.1)) {
      if (s.closed()) return Fail("monitor", protocol::Status::kIoError, "palpa serve went away");
      continue;
    }
    if (n.value("method", "") != "notify_telemetry") continue;
    const json& p = n["params"];
    const json& samples = p["samples"];
    for (size_t k = 0; k < samples["board_time_us"].size(); ++k) {
      if (c.json) {
        PrintJson({{"board_time_us", samples["board_time_us"][k]},
                   {"setpoint_pa", samples["setpoint_pa"][k]},
                   {"measured_pa", samples["measured_pa"][k]},
                   {"finger_output", samples["finger_output"][k]},
                   {"faults", p["faults"]}});
      } else {
        std::string text;
        char v[32];
        for (const json& kpa : samples["measured_pa"][k]) {
          std::snprintf(v, sizeof(v), " %7.2f", kpa.get<double>() / 1000);
          text += v;
        }
        text += "  |";
        for (const json& out : samples["finger_output"][k]) {
          std::snprintf(v, sizeof(v), " %6.3f", out.get<double>());
          text += v;
        }
        std::printf("%10.3f s  kPa%s\n", samples["board_time_us"][k].get<double>() / 1e6,
                    text.c_str());
      }
    }
    std::fflush(stdout);
  }
  return kExitOk;
}

}  // namespace

bool RunsThroughServe(const std::string& command) {
  for (const char* name : {"info", "diag", "set", "line", "monitor", "estop", "clear"}) {
    if (command == name) return true;
  }
  return false;
}

int RunThroughServe(Context& c, const std::string& command, const std::vector<std::string>& args) {
  if (!RunsThroughServe(command)) {
    return Usage(command,
                 "cannot go through palpa serve (--device serve: runs info, diag, set, "
                 "line, monitor, estop and clear; run it where the board is attached)");
  }
  auto served = host::ServedDevice::Open(c.device_uri, "palpa " + command);
  if (!served.ok()) return Fail("", served.status, served.message, kExitConnect);
  host::ServedDevice& s = *served.value;
  if (command == "info") return Info(s, c);
  if (command == "diag") return Diag(s, c);
  if (command == "set") return Set(s, c, args);
  if (command == "line") return Line(s, c, args);
  if (command == "monitor") return Monitor(s, c, args);
  if (!args.empty()) return Usage(command, "takes no arguments");
  if (command == "estop") {  // everyone's right: no control needed
    const host::Outcome o = s.EStop();
    return o.ok() ? kExitOk : Refused("estop", o);
  }
  const auto cleared = s.ClearFault();  // takes control first
  if (!cleared.ok()) return Refused("clear", cleared.outcome());
  if (c.json) PrintJson({{"cleared", cleared.value}});
  return kExitOk;
}

}  // namespace palpa::cli
