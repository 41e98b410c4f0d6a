// palpa: the command line for palpa actuator boards.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "cli.h"

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
        "curves and the reason is printed; --strict-calibration makes that an error (nothing "
        "sent)."}},
      {"line",
       {CmdLine, "line L=VALUE ... [--hold S]",
        "Raw setpoints in kPa for lines (numbered from 1): palpa line 1=30 6=-40"}},
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
        "[--max-cycles N] [--compensator auto|pi|api[:N]] [--previous FILE] [--resume] [--quick] "
        "[--apply]",
        "Runs the thesis calibration of one finger on a rig: zero, regulator correction, then a\n"
        "deformation sweep (pneumatic) or the bias x vacuum indentation grid (jamming) and a\n"
        "hysteresis sweep. Writes DIR/SERIAL.json (the calibration file), SERIAL.csv (raw "
        "readings)\n"
        "and SERIAL.html (report). --rig sim starts palpa-sim serving board and rig (--speed X, "
        "1-10,\n"
        "default 4); a rig FILE names the stage and force sensor (docs/calibration.md). A stopped\n"
        "run keeps DIR/SERIAL.journal.json: --resume continues it. --quick: short settings.\n"
        "--compensator: the model fitted, pi or api with N operators (default 16, 8 with "
        "--quick);\nauto (default) fits both and keeps api where it leaves at most 3/4 of pi's "
        "residual.\n--apply uploads the result to the finger (one staged change)."}},
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
      {"demo",
       {CmdDemo, "demo [--out FILE.svg] [--speed X] [--calibration DIR | --nominal-only]",
        "Starts a simulated thesis-5finger board and plays the thesis's discrimination stimuli:\n"
        "18 three-finger pneumatic combinations and 9 two-finger jamming ones, on the nominal\n"
        "curves; then calibrates the pneumatic fingers on simulated rigs (quick protocol, api) "
        "and\n"
        "plays their stimuli again, compensated. Prints target against achieved, settling and\n"
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
      "                 usb:VID:PID[:SERIAL] (default: $PALPA_DEVICE, else sim:thesis-5finger)\n"
      "  --json         machine-readable output\n\ncommands:\n");
  for (const auto& [name, c] : Commands()) std::fprintf(out, "  %s\n", c.synopsis);
  std::fprintf(out,
               "\npalpa COMMAND --help explains a command. Exit codes: 0 ok, 1 refused or failed,\n"
               "2 bad command line (nothing sent), 3 cannot open the device.\n");
}

}  // namespace

host::Device* Context::Device() {
  if (device) return device.get();
  std::string error;
  auto opened = host::Device::Open(device_uri, options, &error);
  if (!opened.ok()) {
    std::fprintf(stderr, "palpa: cannot open %s: %s\n", device_uri.c_str(), error.c_str());
    return nullptr;
  }
  device = std::move(opened.value);
  if (!device->link().catalog_matches()) {
    std::fprintf(stderr, "palpa: %s runs other firmware: %s. Only flashing is possible.\n",
                 device_uri.c_str(), device->link().Versions().c_str());
  }
  return device.get();
}

int Usage(const std::string& command, const std::string& message) {
  std::fprintf(stderr, "palpa %s: %s\n(see palpa %s --help)\n", command.c_str(), message.c_str(),
               command.c_str());
  return kExitUsage;
}

int Report(const Context& context, const host::Outcome& outcome, const std::string& what) {
  if (!outcome.ok()) {
    std::fprintf(stderr, "palpa %s: %s\n", what.c_str(), outcome.message.c_str());
    return kExitFailed;
  }
  if (!context.json) {
    for (const std::string& note : outcome.notes) std::printf("  %s\n", note.c_str());
  }
  return kExitOk;
}

}  // namespace palpa::cli

int main(int argc, char** argv) {
  using namespace palpa::cli;
  Context context;
  const char* env = std::getenv("PALPA_DEVICE");
  context.device_uri = env != nullptr && *env != '\0' ? env : "sim:thesis-5finger";
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      PrintUsage(stdout);
      return kExitOk;
    }
    if (arg == "--json") {
      context.json = true;
    } else if (arg == "--device") {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "palpa: --device needs a URI, e.g. --device tcp:127.0.0.1:5555\n");
        return kExitUsage;
      }
      context.device_uri = argv[++i];
    } else {
      std::fprintf(stderr, "palpa: unknown option '%s'\n", arg.c_str());
      PrintUsage(stderr);
      return kExitUsage;
    }
  }
  if (i >= argc) {
    PrintUsage(stderr);
    return kExitUsage;
  }
  const std::string name = argv[i];
  const auto& commands = Commands();
  const auto it = commands.find(name);
  if (it == commands.end()) {
    std::fprintf(stderr, "palpa: unknown command '%s'\n", name.c_str());
    PrintUsage(stderr);
    return kExitUsage;
  }
  std::vector<std::string> args(argv + i + 1, argv + argc);
  for (const std::string& a : args) {
    if (a == "--help" || a == "-h") {
      std::printf("usage: palpa [--device URI] [--json] %s\n\n%s\n", it->second.synopsis,
                  it->second.help);
      return kExitOk;
    }
  }
  return it->second.run(context, args);
}
