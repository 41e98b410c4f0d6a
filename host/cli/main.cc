// palpa: the command line for palpa actuator boards.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "cli.h"
#include "sim_state.h"

namespace palpa::cli {
namespace {

struct Command {
  int (*run)(Context&, const std::vector<std::string>&);
  const char* synopsis;
  const char* help;
};

const std::map<std::string, Command>& Commands() {
  static const std::map<std::string, Command> commands = {
      {"list",
       {CmdList, "list", "Serial ports, and HID and USB devices with palpa's USB id (1209:0001)."}},
      {"info",
       {CmdInfo, "info",
        "The board: kind, id, firmware, catalog, configuration, lines and fingers."}},
      {"diag",
       {CmdDiag, "diag",
        "Reset cause, latched and active faults, fault history, loop statistics."}},
      {"config",
       {CmdConfig, "config show|set KEY=VALUE...|load FILE|save|factory-reset",
        "show: the live configuration (JSON with --json).\n"
        "set: change fields, e.g. board.host_timeout_us=200000 line2.slew_pa_per_s=100000\n"
        "     finger4.bias_pa=15000 (lines and fingers numbered from 1); checked locally first.\n"
        "load FILE: a JSON file {\"board\":{...},\"lines\":[...],\"fingers\":[...]} (partial "
        "allowed),\n"
        "     validated as a whole and applied atomically.\n"
        "save: persist the live configuration. factory-reset: back to the compiled-in one."}},
      {"set",
       {CmdSet, "set F=VALUE ... [--hold S] [--strict-calibration]",
        "Fingers (numbered from 1): L2 (level), 0.5 (0..1), 1.2mm (pneumatic), 0.9N/mm (jamming),\n"
        "-10kPa (raw pressure or vacuum). Units are checked per finger kind. Example on\n"
        "thesis-5finger: palpa set 1=L2 2=0.5 3=1.2mm 4=0.9N/mm 5=-10kPa\n"
        "A finger whose calibration file exists but cannot be used falls back to the nominal\n"
        "curves and the reason is printed; --strict-calibration makes that an error (nothing\n"
        "sent). The fingers return to safe as palpa exits and closes its session; --hold S\n"
        "keeps them actuated S seconds first (Ctrl-C, SIGTERM or SIGHUP end the hold early)."}},
      {"line",
       {CmdLine, "line L=VALUE ... [--hold S]",
        "Raw setpoints in kPa for lines (numbered from 1): palpa line 1=30 6=-40\n"
        "The lines return to safe as palpa exits and closes its session; --hold S keeps them\n"
        "there S seconds first (Ctrl-C, SIGTERM or SIGHUP end the hold early)."}},
      {"monitor",
       {CmdMonitor, "monitor [--rate HZ] [--duration S]",
        "A live table of every line (one JSON object per sample with --json); Ctrl-C ends it."}},
      {"record",
       {CmdRecord, "record FILE.csv --duration S",
        "Telemetry to CSV; the first line is a JSON header (board, configuration, units, clock)."}},
      {"estop", {CmdEStop, "estop", "Every line to its safe value now, latched until cleared."}},
      {"clear",
       {CmdClear, "clear",
        "Clear latched faults whose cause is gone; outputs stay safe until new setpoints."}},
      {"calibrate",
       {CmdCalibrate,
        "calibrate --rig FILE|sim --finger N --out DIR [--protocol thesis|adaptive] [--target PCT] "
        "[--max-cycles N] [--compensator auto|pi|api[:N]] [--allow-fallback] [--previous FILE] "
        "[--resume] [--quick] [--apply] [--speed X] [--unit N] [--seed N] [--plant LEVEL] "
        "[--effects LIST]",
        "Runs the thesis calibration of one finger on a rig: zero, regulator correction, then a\n"
        "deformation sweep (pneumatic) or the bias x vacuum indentation grid (jamming) and a\n"
        "hysteresis sweep. Writes DIR/SERIAL.json (the calibration file), SERIAL.csv (raw "
        "readings)\nand SERIAL.html (report). A rig FILE names the stage and force sensor\n"
        "(docs/calibration.md). --rig sim starts palpa-sim serving board and rig: --speed X "
        "(1-10,\n"
        "default 4), --unit N (actuator unit, 0 nominal), --seed N, --plant LEVEL (0-3, default "
        "3)\n"
        "and --effects LIST (creep,rate,history=F) are the simulator's, recorded in the file.\n"
        "A stopped run keeps DIR/SERIAL.journal.json: --resume continues it. --quick: short\n"
        "settings (a 20 kPa sweep; the run says first which compensators it can fit).\n"
        "--compensator: the model fitted, pi or api with N operators (default 16, 8 with --quick,\n"
        "fewer when the sweep tells fewer apart); auto (default) fits both and keeps api where it\n"
        "leaves at most 3/4 of pi's residual. A model that cannot be fitted is an error (nothing\n"
        "written) unless --allow-fallback keeps the static inverse alone. --apply uploads the\n"
        "result to the finger (one staged change)."}},
      {"flash",
       {CmdFlash,
        "flash PACKAGE [--resume] [--dry-run] [--reset-line CHIP:LINE] [--boot-line CHIP:LINE]",
        "Updates the board's firmware over its link: checks the package against the board (kind,\n"
        "anti-rollback counter) and shows the version change, writes the image for the slot the\n"
        "board reports inactive with a progress bar, verifies its SHA-256, activates it for one\n"
        "trial boot, waits for the board to answer on it and confirms it. A board reset before "
        "the\n"
        "confirmation returns to the old image. --resume goes on from what the board reports\n"
        "written; --dry-run checks and says what would happen. --reset-line and --boot-line drive\n"
        "GPIO lines (libgpiod) to start a board whose application cannot run in its bootloader's\n"
        "recovery mode (reset active low, boot active high). docs/flashing.md."}},
      {"package",
       {CmdPackage,
        "package SLOT0.bin SLOT1.bin --version X.Y.Z --counter N [--kind KIND] --out FILE",
        "Makes an update package: each slot's binary (linked to run from that slot) gets the "
        "image\n"
        "header, board kind, slot, anti-rollback counter and SHA-256. KIND: sim (default),\n"
        "mps2-an386, stm32f4."}},
      {"sim",
       {CmdSim, "sim start [--config NAME] [--flash FILE] [--speed X] [--plant N] | stop | status",
        "Keeps one simulated board running for the commands that follow (they use it when no\n"
        "--device or $PALPA_DEVICE names another). Its flash is a file, as a board's flash is a\n"
        "chip: a saved configuration, the boot state and the firmware slots survive 'sim stop' "
        "and\n"
        "the next 'sim start'. --config NAME: thesis-5finger (default), thesis-pneumatic-3,\n"
        "thesis-jamming-2, full-8. --flash FILE: default STATE/sim-CONFIG.flash, STATE being\n"
        "$PALPA_STATE_DIR, else $XDG_STATE_HOME/palpa, else ~/.local/state/palpa.\n"
        "--speed X (0.01-100) and --plant N (0-3) as palpa-sim takes them.\n"
        "Without it, each command starts a throwaway simulated board of its own, and says so."}},
      {"demo",
       {CmdDemo,
        "demo [--out FILE.svg] [--speed X] [--stimuli NAME|FILE]... [--calibration DIR | "
        "--nominal-only]",
        "Starts a simulated thesis-5finger board and plays discrimination stimuli: by default\n"
        "the full thesis sets, 18 three-finger pneumatic combinations and 9 two-finger jamming\n"
        "ones (--stimuli picks a shipped set, e.g. thesis-pneumatic-14, or a stimulus-set file),\n"
        "on the nominal curves; then calibrates the pneumatic fingers on simulated rigs (quick\n"
        "protocol, api) and plays their stimuli again, compensated. Prints target against "
        "achieved, settling and\n"
        "latency, the two passes' errors side by side, and plots the traces. --calibration DIR\n"
        "uses the calibration files in DIR instead (SERIAL.json); --nominal-only stops after the\n"
        "first pass. --speed X: 0.1-10, default 4."}},
  };
  return commands;
}

void PrintUsage(FILE* out) {
  std::fprintf(
      out,
      "usage: palpa [--device URI] [--json] COMMAND [ARGS]\n\n"
      "  --device URI   sim[:CONFIG], serial:PATH[?baud=N], tcp:HOST:PORT, hid:VID:PID[:SERIAL],\n"
      "                 usb:VID:PID[:SERIAL] (default: $PALPA_DEVICE, else the board 'palpa sim\n"
      "                 start' keeps running, else a throwaway sim:thesis-5finger)\n"
      "  --json         every command's output as JSON, errors too: {\"error\": {\"status\", "
      "...}}\n\n"
      "commands:\n");
  for (const auto& [name, c] : Commands()) std::fprintf(out, "  %s\n", c.synopsis);
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
  std::string error;
  options.number_from = 1;  // as the command line numbers fingers and lines
  auto opened = host::Device::Open(device_uri, options, &error);
  if (!opened.ok()) {
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
      std::printf("usage: palpa [--device URI] [--json] %s\n\n%s\n", it->second.synopsis,
                  it->second.help);
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
  if (context.device_uri.empty()) context.device_uri = "sim:thesis-5finger";
  context.throwaway = context.device_uri.rfind("sim", 0) == 0 && !OwnsItsBoards(name);
  const int rc = it->second.run(context, args);
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
