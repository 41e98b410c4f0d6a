// palpa set, palpa line: fingers in people's terms, raw line setpoints.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "cli.h"

namespace palpa::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;

/// Splits off "--hold S"; false with *error on a bad value.
bool TakeHold(std::vector<std::string>& args, double& hold_s, std::string* error) {
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] != "--hold") continue;
    if (i + 1 >= args.size() || !ParseNumber(args[i + 1], hold_s) || hold_s < 0) {
      *error = "--hold needs a number of seconds (0 or more)";
      return false;
    }
    args.erase(args.begin() + static_cast<long>(i), args.begin() + static_cast<long>(i) + 2);
    return true;
  }
  return true;
}

/// Keeps the session (and so the actuation) alive; the board goes safe once palpa has gone quiet.
void Hold(const Context& c, double hold_s) {
  if (hold_s <= 0) {
    if (!c.json) {
      std::printf(
          "note: the board returns to its safe state within its host-silence timeout once palpa "
          "exits;\n"
          "      use --hold SECONDS, or keep a session open (palpa monitor), to hold it.\n");
    }
    return;
  }
  std::signal(SIGINT, [](int) { g_interrupted = 1; });
  for (double t = 0; t < hold_s && !g_interrupted; t += 0.05)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
}

}  // namespace

int CmdSet(Context& c, const std::vector<std::string>& given) {
  std::vector<std::string> args = given;
  double hold_s = 0;
  std::string hold_error;
  if (!TakeHold(args, hold_s, &hold_error)) return Usage("set", hold_error);
  const auto strict = std::find(args.begin(), args.end(), "--strict-calibration");
  if (strict != args.end()) {
    c.options.invalid_calibration_is_error = true;
    args.erase(strict);
  }
  if (args.empty())
    return Usage("set", "expected at least one F=VALUE, e.g. palpa set 1=L2 4=0.9N/mm");
  std::vector<host::FingerRequest> requests;
  for (const std::string& a :
       args) {  // syntax first: a malformed line sends nothing, not even Hello
    host::FingerRequest r;
    std::string error;
    if (!ParseFingerArgument(a, protocol::kMaxFingers, r, &error)) return Usage("set", error);
    requests.push_back(r);
  }
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const int rc = Report(c, d->Set(requests), "set");
  if (rc != kExitOk) return rc;
  if (c.json) std::printf("{\"applied\":true}\n");
  Hold(c, hold_s);
  return rc;
}

int CmdLine(Context& c, const std::vector<std::string>& given) {
  std::vector<std::string> args = given;
  double hold_s = 0;
  std::string hold_error;
  if (!TakeHold(args, hold_s, &hold_error)) return Usage("line", hold_error);
  if (args.empty())
    return Usage("line", "expected at least one L=VALUE in kPa, e.g. palpa line 1=30 6=-40");
  std::vector<std::pair<uint8_t, double>> setpoints;
  for (const std::string& a : args) {
    std::pair<uint8_t, double> s;
    std::string error;
    if (!ParseLineArgument(a, protocol::kMaxLines, s, &error)) return Usage("line", error);
    setpoints.push_back(s);
  }
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const int rc = Report(c, d->SetLines(setpoints), "line");
  if (rc != kExitOk) return rc;
  if (c.json) std::printf("{\"applied\":true}\n");
  Hold(c, hold_s);
  return rc;
}

}  // namespace palpa::cli
