// palpa: the command line for palpa actuator boards.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include "cli.h"
#include "sim_state.h"

namespace palpa::cli {
namespace {

/// Every command, by name: each is defined beside its handler (cmd_*.cc).
const std::map<std::string, const Command*>& Commands() {
  static const std::map<std::string, const Command*> commands = [] {
    std::map<std::string, const Command*> by_name;
    for (const Command* c :
         {&kListCommand,      &kInfoCommand,    &kDiagCommand,    &kConfigCommand, &kSetCommand,
          &kLineCommand,      &kMonitorCommand, &kRecordCommand,  &kEStopCommand,  &kClearCommand,
          &kCalibrateCommand, &kFlashCommand,   &kPackageCommand, &kKeygenCommand, &kSimCommand,
          &kDemoCommand,      &kSceneCommand,   &kRenderCommand,  &kServeCommand,  &kStudyCommand})
      by_name[c->name] = c;
    return by_name;
  }();
  return commands;
}

void PrintUsage(FILE* out) {
  std::fprintf(
      out,
      "usage: palpa [--device URI] [--json] COMMAND [ARGS]\n\n"
      "  --device URI   sim[:CONFIG], serial:PATH[?baud=N], tcp:HOST:PORT, hid:VID:PID[:SERIAL],\n"
      "                 usb:VID:PID[:SERIAL], serve:HOST:PORT (a board behind palpa serve: info,\n"
      "                 diag, set, line, monitor, estop, clear) (default: $PALPA_DEVICE, else the\n"
      "                 board 'palpa sim start' keeps running, else a throwaway "
      "sim:thesis-5finger)\n"
      "  --json         every command's output as JSON, errors too: {\"error\": {\"status\", "
      "...}}\n\n"
      "commands:\n");
  for (const auto& [name, c] : Commands()) std::fprintf(out, "  %s\n", c->synopsis);
  std::fprintf(
      out,
      "\nFingers and lines are numbered from 1. palpa COMMAND --help explains a command.\n"
      "Exit codes: 0 ok, 1 refused or failed, 2 bad command line (nothing sent), 3 cannot\n"
      "open the device or another host holds it (busy). Every command closes its session with\n"
      "the board when it ends, on Ctrl-C, SIGTERM and SIGHUP too: the board's outputs go safe,\n"
      "no fault latched.\n");
}

/// Commands that run without a device, or on simulators of their own whatever --device says.
bool OwnsItsBoards(const std::string& command) {
  return command == "demo" || command == "sim" || command == "list" || command == "package";
}

/// Commands that use the board `palpa sim start` keeps when no device is named: not calibrate,
/// whose simulated rig comes with a simulated board of its own.
bool UsesKeptSim(const std::string& command) {
  return !OwnsItsBoards(command) && command != "calibrate";
}

}  // namespace

host::Device* Context::Device() {
  if (device) return device.get();
  options.number_from = number_from;  // from 1, as the command line numbers fingers and lines
  auto opened = host::Device::Open(device_uri, options, truth_wanted ? &truth_address : nullptr);
  if (!opened.ok()) {
    const std::string& error = opened.message;
    // The transports' messages name the device already, most of them; a busy board's says
    // "busy: another host holds the board (...)" and stands alone.
    const bool named = error.find(device_uri) != std::string::npos;
    const bool busy = opened.status == protocol::Status::kBusy;
    Fail("", opened.status,
         busy ? error : "cannot open " + (named ? error : device_uri + ": " + error), kExitConnect);
    return nullptr;
  }
  device = std::move(opened.value);
  closed_on_signal = std::make_unique<ClosedOnSignal>(device.get());
  if (!device->link().catalog_matches()) {  // on stderr: with --json too
    std::fprintf(stderr, "palpa: %s runs other firmware: %s. Only flashing is possible.\n",
                 device_uri.c_str(), device->link().Versions().c_str());
  }
  return device.get();
}

}  // namespace palpa::cli

int main(int argc, char** argv) {
  using namespace palpa::cli;
  StartSignalWatch();  // first: every thread after it leaves the signals to the watch
  Context context;
  std::string device_option;
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      PrintUsage(stdout);
      return kExitOk;
    }
    if (arg == "--json") {
      context.json = true;
      SetJsonOutput(true);
    } else if (arg == "--device") {
      if (i + 1 >= argc || argv[i + 1][0] == '-') {
        return Usage("", "--device: a value is missing, e.g. --device tcp:127.0.0.1:5555");
      }
      device_option = argv[++i];
    } else {
      const std::string near = Suggest(arg, {"--json", "--device", "--help"});
      Usage("",
            "unknown option '" + arg + "'" + (near.empty() ? "" : " (did you mean " + near + "?)"));
      if (!context.json) PrintUsage(stderr);
      return kExitUsage;
    }
  }
  if (i >= argc) {
    if (context.json) return Usage("", "a COMMAND is missing (palpa --help lists them)");
    PrintUsage(stderr);
    return kExitUsage;
  }
  const std::string name = argv[i];
  const auto& commands = Commands();
  const auto it = commands.find(name);
  if (it == commands.end()) {
    std::vector<std::string> names;
    for (const auto& [known, c] : commands) names.push_back(known);
    const std::string near = Suggest(name, names);
    return Usage(
        "", "unknown command '" + name + "'" +
                (near.empty() ? " (palpa --help lists them)" : " (did you mean '" + near + "'?)"));
  }
  std::vector<std::string> args(argv + i + 1, argv + argc);
  for (const std::string& a : args) {
    if (a == "--help" || a == "-h") {
      std::printf("usage: palpa [--device URI] [--json] %s\n\n%s\n", it->second->synopsis,
                  it->second->help);
      return kExitOk;
    }
  }
  // Which board: --device, $PALPA_DEVICE, the one 'palpa sim start' keeps, or a throwaway one.
  const char* env = std::getenv("PALPA_DEVICE");
  std::string gone;
  if (!device_option.empty()) {
    context.device_uri = device_option;
  } else if (env != nullptr && *env != '\0') {
    context.device_uri = env;
  } else if (UsesKeptSim(name)) {
    if (const auto sim = FindRunningSim(&gone)) context.device_uri = sim->uri;
  }
  if (context.device_uri.empty()) {
    context.device_uri = "sim:thesis-5finger";
    context.device_defaulted = true;
  }
  context.throwaway = context.device_uri.rfind("sim", 0) == 0 && !OwnsItsBoards(name);
  if (context.device_uri.rfind("serve:", 0) == 0 && !OwnsItsBoards(name))
    return RunThroughServe(context, name, args);
  const int rc = it->second->run(context, args);
  if (context.device && context.throwaway) {
    if (!gone.empty()) std::fprintf(stderr, "palpa: %s.\n", gone.c_str());
    std::fprintf(stderr,
                 "palpa: this ran on a throwaway simulated board (%s), gone now with whatever the "
                 "command changed;\n       'palpa sim start' keeps one board running for the "
                 "commands that follow.\n",
                 context.device_uri.c_str());
  }
  return rc;
}
