// palpa sim start|stop|status: one simulated board kept running across commands, its flash in a
// file so that what it saved survives as a board's does.
#include <cstdio>

#include "cli.h"
#include "palpa/host/device_uri.h"
#include "sim_state.h"

namespace palpa::cli {
namespace {

nlohmann::ordered_json SimJson(const RunningSim& sim) {
  return {{"running", true},    {"pid", sim.pid}, {"device", sim.uri},     {"config", sim.config},
          {"flash", sim.flash}, {"log", sim.log}, {"started", sim.started}};
}

int Start(const std::vector<std::string>& args) {
  std::string config = "thesis-5finger", flash;
  std::vector<std::string> options;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a != "--config" && a != "--flash" && a != "--speed" && a != "--plant") {
      return Usage("sim", "start: unexpected argument '" + a +
                              "' (expected --config, --flash, --speed, --plant)");
    }
    const host::Result<std::string> option = OptionValue(args, i);
    if (!option.ok()) return Usage("sim", "start: " + option.message);
    const std::string& value = option.value;
    ++i;
    if (a == "--config") {
      if (const std::string why = host::SimConfigError(value); !why.empty())
        return Usage("sim", "start: --config " + value + ": " + why);
      config = value;
    } else if (a == "--flash") {
      flash = value;
    } else {
      double n = 0;
      if (!ParseNumber(value, n)) return Usage("sim", "start: " + a + " " + value + ": a number");
      options.push_back(a);
      options.push_back(value);
    }
  }
  std::string gone;
  if (const auto running = FindRunningSim(&gone)) {
    return Fail("sim", protocol::Status::kBusy,
                "a simulated " + running->config + " board is already running (pid " +
                    std::to_string(running->pid) + ", " + running->uri +
                    "); 'palpa sim stop' ends it");
  }
  if (flash.empty()) flash = SimStateDir() + "/sim-" + config + ".flash";
  const host::Result<RunningSim> started = StartSim(config, flash, options);
  if (!started.ok()) return Fail("sim", started.status, started.message);
  const RunningSim& sim = started.value;
  if (JsonOutput()) {
    PrintJson(SimJson(sim));
  } else {
    std::printf(
        "simulated %s board running (pid %d) on %s\n"
        "  flash: %s (what 'palpa config save' keeps survives 'palpa sim stop')\n"
        "  the commands that follow use it; 'palpa sim stop' ends it\n",
        sim.config.c_str(), sim.pid, sim.uri.c_str(), sim.flash.c_str());
  }
  return kExitOk;
}

int Stop() {
  std::string gone;
  const auto sim = FindRunningSim(&gone);
  if (!sim) {
    if (JsonOutput()) {
      PrintJson({{"running", false}, {"stopped", false}});
    } else {
      std::printf("no simulated board is running%s\n",
                  gone.empty() ? "" : (" (" + gone + ")").c_str());
    }
    return kExitOk;
  }
  if (const host::Outcome o = StopSim(*sim); !o.ok()) return Fail("sim", o.status, o.message);
  if (JsonOutput()) {
    PrintJson({{"running", false}, {"stopped", true}, {"pid", sim->pid}, {"flash", sim->flash}});
  } else {
    std::printf("stopped the simulated %s board (pid %d); its flash stays in %s\n",
                sim->config.c_str(), sim->pid, sim->flash.c_str());
  }
  return kExitOk;
}

int Status() {
  std::string gone;
  const auto sim = FindRunningSim(&gone);
  if (JsonOutput()) {
    PrintJson(sim ? SimJson(*sim) : nlohmann::ordered_json{{"running", false}});
    return kExitOk;
  }
  if (!sim) {
    std::printf(
        "no simulated board is running%s: each command starts a throwaway one\n"
        "('palpa sim start' keeps one running)\n",
        gone.empty() ? "" : (" (" + gone + ")").c_str());
    return kExitOk;
  }
  std::printf("simulated %s board running since %s (pid %d) on %s\n  flash: %s\n  log:   %s\n",
              sim->config.c_str(), sim->started.c_str(), sim->pid, sim->uri.c_str(),
              sim->flash.c_str(), sim->log.c_str());
  return kExitOk;
}

}  // namespace

int CmdSim(Context&, const std::vector<std::string>& args) {
  if (args.empty()) return Usage("sim", "expected start, stop or status");
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args[0] == "start") return Start(rest);
  if (!rest.empty()) return Usage("sim", args[0] + " takes no arguments");
  if (args[0] == "stop") return Stop();
  if (args[0] == "status") return Status();
  const std::string near = Suggest(args[0], {"start", "stop", "status"});
  return Usage("sim", "unknown subcommand '" + args[0] + "'" +
                          (near.empty() ? " (expected start, stop or status)"
                                        : " (did you mean '" + near + "'?)"));
}

const Command kSimCommand{
    "sim", "sim start [--config NAME] [--flash FILE] [--speed X] [--plant N] | stop | status",
    "Keeps one simulated board running for the commands that follow (they use it when no\n"
    "--device or $PALPA_DEVICE names another). Its flash is a file, as a board's flash is a\n"
    "chip: a saved configuration, the boot state and the firmware slots survive 'sim stop' "
    "and\n"
    "the next 'sim start'. --config NAME: thesis-5finger (default), thesis-pneumatic-3,\n"
    "thesis-jamming-2, full-8. --flash FILE: default STATE/sim-CONFIG.flash, STATE being\n"
    "$PALPA_STATE_DIR, else $XDG_STATE_HOME/palpa, else ~/.local/state/palpa.\n"
    "--speed X (0.01-100) and --plant N (0-3) as palpa-sim takes them.\n"
    "Without it, each command starts a throwaway simulated board of its own, and says so.",
    CmdSim};

}  // namespace palpa::cli
