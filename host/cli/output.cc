// What every command prints on failure, as text or with --json as {"error": {...}}.
#include <cstdio>

#include "cli.h"

namespace palpa::cli {
namespace {

bool g_json = false;

}  // namespace

void SetJsonOutput(bool json) { g_json = json; }
bool JsonOutput() { return g_json; }
FILE* TextOut() { return g_json ? stderr : stdout; }

void PrintJson(const nlohmann::ordered_json& j) {
  std::printf("%s\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
  std::fflush(stdout);
}

int Fail(const std::string& what, protocol::Status status, const std::string& message,
         int exit_code) {
  if (g_json) {
    PrintJson({{"error",
                {{"status", protocol::StatusName(status)},
                 {"message", message},
                 {"command", what},
                 {"exit_code", exit_code}}}});
  } else {
    std::fprintf(stderr, "palpa%s%s: %s\n", what.empty() ? "" : " ", what.c_str(), message.c_str());
  }
  return exit_code;
}

int Usage(const std::string& command, const std::string& message) {
  if (g_json) return Fail(command, protocol::Status::kInvalidArgument, message, kExitUsage);
  const std::string space = command.empty() ? "" : " ";
  std::fprintf(stderr, "palpa%s%s: %s\n(see palpa%s%s --help)\n", space.c_str(), command.c_str(),
               message.c_str(), space.c_str(), command.c_str());
  return kExitUsage;
}

void WarnCurves(host::Device& device) {
  for (const host::CurveWarning& w : device.curve_warnings())
    std::fprintf(stderr, "palpa: warning: %s\n", w.message.c_str());
}

int Report(const Context& context, const host::Outcome& outcome, const std::string& what) {
  if (!outcome.ok()) return Fail(what, outcome.status, outcome.message);
  if (!context.json) {
    for (const std::string& note : outcome.notes) std::printf("  %s\n", note.c_str());
  }
  return kExitOk;
}

}  // namespace palpa::cli
