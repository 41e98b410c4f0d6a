// palpa calibrate's command line parsed and checked (calibrate_args.h).
#include "calibrate_args.h"

#include <sys/stat.h>

#include <cmath>
#include <cstdlib>

#include "cli.h"
#include "sim_options.h"

namespace palpa::cli {

bool ParseCompensator(const std::string& text, std::optional<protocol::CompensatorKind>& kind,
                      int& operators) {
  const size_t colon = text.find(':');
  const std::string name = text.substr(0, colon);
  if (name == "auto") {
    kind.reset();
  } else if (name == "pi") {
    kind = protocol::CompensatorKind::kPrandtlIshlinskii;
  } else if (name == "api") {
    kind = protocol::CompensatorKind::kAsymmetricPi;
  } else {
    return false;
  }
  operators = 0;
  if (colon == std::string::npos) return true;
  double n = 0;
  if (!ParseNumber(text.substr(colon + 1), n) || n < 1 || n > 32 || n != std::floor(n))
    return false;
  operators = static_cast<int>(n);
  return true;
}

/// The command line into `a`; a usage error's exit code when it is malformed, else kExitOk.
int ParseCalibrateArgs(const std::vector<std::string>& args, CalibrateArgs& a) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= args.size()) return false;
      out = args[++i];
      return true;
    };
    std::string v;
    if (arg == "--resume") {
      a.resume = true;
    } else if (arg == "--quick") {
      a.quick = true;
    } else if (arg == "--apply") {
      a.apply = true;
    } else if (arg == "--allow-fallback") {
      a.allow_fallback = true;
    } else if (const host::Result<bool> sim = ParseSimPlantOption(arg, value, a.plant);
               !sim.ok() || sim.value) {
      if (!sim.ok()) return Usage("calibrate", sim.message);
      a.plant_options = true;
    } else if (arg == "--rig") {
      if (!value(a.rig)) return Usage("calibrate", "--rig needs FILE or sim");
    } else if (arg == "--out") {
      if (!value(a.out)) return Usage("calibrate", "--out needs a directory");
    } else if (arg == "--protocol") {
      if (!value(a.protocol) || (a.protocol != "thesis" && a.protocol != "adaptive"))
        return Usage("calibrate", "--protocol " + a.protocol + ": expected thesis or adaptive");
    } else if (arg == "--target") {
      if (!value(v) || !ParseNumber(v, a.target_pct) || a.target_pct < 0.5 || a.target_pct > 50)
        return Usage("calibrate", "--target " + v + ": expected a map error of 0.5 to 50 (%)");
    } else if (arg == "--max-cycles") {
      double n = 0;
      if (!value(v) || !ParseNumber(v, n) || n < 6 || n > 200 || n != std::floor(n))
        return Usage("calibrate", "--max-cycles " + v + ": expected 6 to 200 indentation cycles");
      a.max_cycles = static_cast<int>(n);
    } else if (arg == "--compensator") {
      if (!value(v) || !ParseCompensator(v, a.compensator, a.operators))
        return Usage(
            "calibrate",
            "--compensator " + v + ": expected auto, pi or api, optionally :OPERATORS (1 to 32)");
    } else if (arg == "--previous") {
      if (!value(a.previous)) return Usage("calibrate", "--previous needs a calibration file");
    } else if (arg == "--finger") {
      double n = 0;
      if (!value(v) || !ParseNumber(v, n) || n < 1 || n > 8 || n != std::floor(n)) {
        return Usage("calibrate", "--finger " + v + ": expected a finger number 1 to 8");
      }
      a.finger = static_cast<int>(n) - 1;
    } else if (arg == "--speed") {
      // Faster, the board's 100 ms host-silence timeout is a few ms of real time: too short for
      // a host sharing its cores with the simulator, whose board then goes safe mid-run.
      if (!value(v) || !ParseNumber(v, a.speed) || a.speed < 1 || a.speed > 10) {
        return Usage(
            "calibrate",
            "--speed " + v + ": expected 1 to 10 (palpa-sim's time scale, --rig sim only)");
      }
    } else {
      return Usage("calibrate", "unexpected argument '" + arg + "'");
    }
  }
  return kExitOk;
}

/// What the arguments say together, and the output directory, checked before anything starts:
/// a refused command leaves nothing (the directory is made only once everything is checked).
int CheckCalibrateArgs(const CalibrateArgs& a) {
  if (a.rig.empty() || a.finger < 0 || a.out.empty()) {
    return Usage("calibrate", "needs --rig FILE|sim, --finger N and --out DIR");
  }
  if (a.plant_options && a.rig != "sim")
    return Usage("calibrate", "--unit, --seed, --plant and --effects go with --rig sim");
  // The rig's simulator takes its options from the command line, so the file can say which unit
  // it calibrated; an environment variable it would not read must not look as if it did.
  if (const char* env = getenv("PALPA_SIM_ARGS"); a.rig == "sim" && env != nullptr && *env) {
    return Usage("calibrate",
                 std::string("PALPA_SIM_ARGS ('") + env +
                     "') is not read by --rig sim: give calibrate the simulator's options "
                     "(--unit, --seed, --plant, --effects, --speed)");
  }
  struct stat st {};
  const bool out_exists = stat(a.out.c_str(), &st) == 0;
  if (out_exists && !S_ISDIR(st.st_mode))
    return Usage("calibrate", "--out " + a.out + ": not a directory");
  if (!out_exists && a.resume)
    return Usage("calibrate",
                 "--resume: --out " + a.out + " does not exist (no journal to resume)");
  return kExitOk;
}

}  // namespace palpa::cli
