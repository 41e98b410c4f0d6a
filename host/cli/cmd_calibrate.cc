// palpa calibrate: the thesis protocol on a rig (lab hardware by a rig file, or palpa-sim's rig),
// with a progress bar and time remaining, a journal to resume from, and the calibration file,
// raw data and an HTML report written to the output directory.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <sstream>

#include "cli.h"
#include "palpa/calibration/calibration_protocol.h"
#include "palpa/calibration/device_rig.h"
#include "palpa/calibration/report.h"
#include "palpa/calibration/rig_file.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"
#include "palpa/host/transport.h"
#include "sim_rig.h"

namespace palpa::cli {
namespace {

namespace cal = calibration;

struct CalibrateArgs {
  std::string rig;
  int finger = -1;
  std::string protocol = "thesis";
  std::string out;
  bool resume = false;
  bool quick = false;
  bool apply = false;
  double speed = 4;
  double target_pct = 2.5;
  int max_cycles = 18;
  std::optional<protocol::CompensatorKind> compensator;  ///< empty: the better of pi and api
  int operators = 0;     ///< 0: the protocol's default (16, or 8 with --quick)
  std::string previous;  ///< empty: DIR/SERIAL.json when there is one
  /// A compensator that cannot be fitted leaves the static inverse alone instead of failing.
  bool allow_fallback = false;
  host::SimulatedPlant plant;  ///< --rig sim: the simulator's unit, seed, level and effects
  bool plant_options = false;  ///< one of them was given
};

std::string UtcNow() {
  const std::time_t t = std::time(nullptr);
  char b[32];
  std::strftime(b, sizeof(b), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return b;
}

void ProgressBar(const cal::Progress& p, std::chrono::steady_clock::time_point start) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double left = p.done > 0 ? elapsed * (p.total - p.done) / p.done : 0;
  const int width = 30, filled = p.total > 0 ? width * p.done / p.total : 0;
  std::fprintf(stderr, "\r[%s%s] %3d/%d  %s left  %-48.48s",
               std::string(static_cast<size_t>(filled), '#').c_str(),
               std::string(static_cast<size_t>(width - filled), '.').c_str(), p.done, p.total,
               p.done > 0 ? (std::to_string(static_cast<int>(left / 60)) + "m" +
                             std::to_string(static_cast<int>(left) % 60) + "s")
                                .c_str()
                          : "--",
               p.step.c_str());
  std::fflush(stderr);
}

}  // namespace

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

int CmdCalibrate(Context& c, const std::vector<std::string>& args) {
  CalibrateArgs a;
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
    } else if (std::string why; ParseSimPlantOption(arg, value, a.plant, &why)) {
      if (!why.empty()) return Usage("calibrate", why);
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
  // The directory is made only once everything is checked: a refused command leaves nothing.
  struct stat st {};
  const bool out_exists = stat(a.out.c_str(), &st) == 0;
  if (out_exists && !S_ISDIR(st.st_mode))
    return Usage("calibrate", "--out " + a.out + ": not a directory");
  if (!out_exists && a.resume)
    return Usage("calibrate",
                 "--resume: --out " + a.out + " does not exist (no journal to resume)");

  // The rig and the board: palpa-sim serving both, or a rig file and --device.
  std::string error;
  std::optional<cal::RigDescription> description;
  host::Device* device = nullptr;
  std::optional<SimRig> sim;
  std::optional<cal::RigDevices> lab_devices;
  cal::RigDevices* devices = nullptr;
  if (a.rig == "sim") {
    if (!c.device_uri.empty() && c.device_uri.rfind("sim", 0) != 0) {
      return Usage("calibrate", "--rig sim goes with a simulated device (--device sim[:CONFIG])");
    }
    const std::string config = c.device_uri.size() > 4 ? c.device_uri.substr(4) : "thesis-5finger";
    sim = OpenSimRig(config, a.finger, a.speed, a.plant, &error);
    if (!sim) return Fail("calibrate", protocol::Status::kUnavailable, error, kExitConnect);
    device = sim->device.get();
    description = sim->description;
    devices = &sim->devices;
  } else {
    description = cal::LoadRigDescription(a.rig, &error);
    if (!description) return Usage("calibrate", "--rig " + error);
    device = c.Device();
    if (device == nullptr) return kExitConnect;
  }
  if (a.finger >= device->info().finger_count) {
    return Usage("calibrate", "--finger " + std::to_string(a.finger + 1) + ": the board has " +
                                  std::to_string(device->info().finger_count) + " fingers");
  }
  if (devices == nullptr) {
    lab_devices = cal::OpenRigDevices(*description, &error);
    if (!lab_devices) {
      return Fail("calibrate", protocol::Status::kUnavailable,
                  "rig " + description->name + ": " + error, kExitConnect);
    }
    devices = &*lab_devices;
  }
  const auto finger_config = device->ReadFinger(static_cast<uint8_t>(a.finger), &error);
  if (!finger_config.ok()) return Fail("calibrate", finger_config.status, error);
  const std::string serial(finger_config.value.actuator_serial.data(),
                           strnlen(finger_config.value.actuator_serial.data(),
                                   finger_config.value.actuator_serial.size()));
  if (!host::ValidSerial(serial)) {
    return Fail("calibrate", protocol::Status::kBadValue,
                "finger " + std::to_string(a.finger + 1) + " has no usable actuator serial ('" +
                    serial + "'); set it with palpa config set");
  }
  // What the sweep allows, said before anything runs; a compensator it cannot fit is refused
  // now rather than after the whole run.
  cal::ProtocolOptions options = a.quick ? cal::QuickProtocol() : cal::ProtocolOptions{};
  if (a.protocol == "adaptive") options.map_protocol = cal::MapProtocol::kAdaptive;
  options.compensator = a.compensator;
  if (a.operators > 0) options.compensator_operators = a.operators;
  options.adaptive.target_error = a.target_pct / 100;
  options.adaptive.max_cycles = a.max_cycles;
  options.adaptive.min_cycles = std::min(options.adaptive.min_cycles, a.max_cycles);
  const bool jamming = device->info().fingers[a.finger].kind == protocol::FingerKind::kJamming;
  const cal::SweepCapacity sweep = cal::SweepFor(options, jamming);
  std::fprintf(TextOut(), "hysteresis sweep%s: %s\n", a.quick ? " (--quick)" : "",
               sweep.Describe(options.compensator).c_str());
  std::fflush(TextOut());
  if (const std::string why = sweep.Refusal(options.compensator); !why.empty()) {
    if (!a.allow_fallback) {
      return Usage("calibrate", "--compensator: " + why +
                                    "; ask for fewer operators, or --allow-fallback to keep the "
                                    "static inverse alone");
    }
    std::fprintf(TextOut(),
                 "  note: %s; with --allow-fallback the file will have the static inverse alone\n",
                 why.c_str());
  }

  cal::DeviceBoardPort board(*device);
  cal::BoardTime time(*device);
  cal::Rig rig{*devices->stage,   *devices->force,           board, time, description->limits,
               description->name, description->force_noise_n};
  // Another run (of another finger) may have made it meanwhile: only a failure to have it counts.
  if (!out_exists && mkdir(a.out.c_str(), 0755) != 0 &&
      !(errno == EEXIST && stat(a.out.c_str(), &st) == 0 && S_ISDIR(st.st_mode))) {
    return Fail("calibrate", protocol::Status::kIoError,
                "cannot create --out " + a.out + ": " + std::strerror(errno));
  }
  const std::string base = a.out + "/" + serial;
  cal::Journal journal;
  if (a.resume) {
    const std::string path = base + ".journal.json";
    struct stat journal_stat;
    if (lstat(path.c_str(), &journal_stat) != 0)
      return Usage("calibrate", "--resume: no journal " + path);
    auto state = cal::LoadJournal(path, &error);
    if (!state) return Usage("calibrate", "--resume: " + error + " (nothing was started)");
    journal.state = std::move(*state);
  }
  journal.save = [&base](const cal::Journal& j) {
    std::string why;
    if (!host::WriteFileWhole(base + ".journal.json", j.state.dump(), &why)) {
      std::fprintf(stderr,
                   "\npalpa calibrate: journal not saved (%s): a stopped run cannot resume\n",
                   why.c_str());
    }
  };
  // The actuator's last calibration, for the detector that notices it changed.
  std::optional<host::CalibrationFile> previous;
  const std::string previous_path = a.previous.empty() ? base + ".json" : a.previous;
  if (!a.previous.empty() || access(previous_path.c_str(), F_OK) == 0) {
    previous = host::LoadCalibration(previous_path, &error);
    if (!previous) return Usage("calibrate", "previous calibration " + error);
    if (previous->actuator_serial != serial) {
      return Usage("calibrate", "--previous " + previous_path + ": calibrates " +
                                    previous->actuator_serial + ", not " + serial);
    }
  }
  cal::RunInfo info{serial,          device->info().board_id,        UtcNow(), description->name,
                    serial + ".csv", previous ? &*previous : nullptr};
  if (sim) info.simulation = a.plant;
  cal::CalibrationRun run;
  const auto start = std::chrono::steady_clock::now();
  const cal::RigStatus s = cal::RunCalibration(
      rig, static_cast<uint8_t>(a.finger), options, info, journal,
      [&](const cal::Progress& p) { ProgressBar(p, start); }, &run);
  std::fprintf(stderr, "\n");
  if (!s.ok) {
    return Fail("calibrate", protocol::Status::kUnavailable,
                "stopped: " + s.error +
                    "\nThe stage was retracted and the board vented. What was finished is in " +
                    base + ".journal.json; run again with --resume to continue.");
  }
  if (!run.fit.ok() && !a.allow_fallback) {
    return Fail("calibrate", protocol::Status::kBadValue,
                "the compensator could not be fitted: " + run.fit.error +
                    "\nNothing was written; the measurements are kept in " + base +
                    ".journal.json: run again with --resume and another --compensator, or with "
                    "--allow-fallback to keep the static inverse alone.");
  }
  std::string csv;
  for (const std::string& row : run.csv) csv += row + "\n";
  if (!host::WriteFileWhole(base + ".csv", csv, &error) ||
      !host::SaveCalibration(run.file, base + ".json", &error) ||
      !host::WriteFileWhole(base + ".html", cal::RenderReport(run), &error)) {
    return Fail("calibrate", protocol::Status::kIoError,
                "cannot write the results in " + a.out + ": " + error);
  }
  unlink((base + ".journal.json").c_str());
  std::fprintf(TextOut(), "calibrated %s (finger %d%s): %s.json, %s.csv, %s.html\n", serial.c_str(),
               a.finger + 1, sim ? (", " + DescribeSimulatedPlant(a.plant)).c_str() : "",
               base.c_str(), base.c_str(), base.c_str());
  if (run.file.rising_fit) {
    std::fprintf(TextOut(),
                 "  deformation branches: rising %.4f, falling %.4f µm/Pa (Table 5-4: 0.0428, "
                 "0.0475 mm/kPa, the same unit)\n",
                 run.file.rising_fit->slope, run.file.falling_fit->slope);
  }
  if (run.file.recommended_bias_pa)
    std::fprintf(TextOut(), "  recommended bias: %.0f Pa\n", *run.file.recommended_bias_pa);
  if (run.file.quality.map_error) {
    std::fprintf(TextOut(), "  stiffness map: %s, %d cycles, cross-validated error %.1f %%\n",
                 run.file.quality.protocol.c_str(), run.file.quality.cycles,
                 100 * *run.file.quality.map_error);
  }
  for (const host::QualityCheck& k : run.file.quality.checks) {
    std::fprintf(TextOut(), "  check %-10s %s  %s\n", k.name.c_str(), k.passed ? "pass" : "FAIL",
                 k.detail.c_str());
  }
  for (const std::string& flag : run.file.quality.flags) {
    const bool from_check =
        std::any_of(run.file.quality.checks.begin(), run.file.quality.checks.end(),
                    [&](const host::QualityCheck& k) {
                      return !k.passed && flag.rfind(k.name + ": ", 0) == 0;
                    });
    if (!from_check) std::fprintf(TextOut(), "  note: %s\n", flag.c_str());
  }
  if (!run.compensator_choice.empty()) {
    std::fprintf(TextOut(), "  model chosen (auto): %s (%s)\n", run.compensator_choice.c_str(),
                 run.file.kind == protocol::FingerKind::kJamming ? "mN/mm" : "µm");
  }
  if (!run.fit.ok()) {
    std::fprintf(TextOut(), "  compensator none: the static inverse alone (--allow-fallback)\n");
  } else {
    std::fprintf(TextOut(),
                 "  compensator %s (%d of its %d operators carry a weight), fit residual %.1f "
                 "RMS, %.1f max (%s)\n",
                 host::CompensatorLabel(run.file).c_str(), run.fit.operators_used,
                 run.fit.operators, run.file.quality.residual_rms, run.file.quality.residual_max,
                 jamming ? "mN/mm" : "µm");
  }
  if (a.apply) {
    const host::Outcome o = device->ApplyCalibration(static_cast<uint8_t>(a.finger), run.file);
    if (!o.ok()) return Report(c, o, "apply calibration");
    std::fprintf(TextOut(),
                 "  applied to finger %d (static inverse, compensator, regulator correction%s)\n",
                 a.finger + 1, run.file.recommended_bias_pa ? ", bias" : "");
  }
  if (c.json) {
    nlohmann::ordered_json checks = nlohmann::ordered_json::array();
    for (const host::QualityCheck& k : run.file.quality.checks)
      checks.push_back({{"name", k.name}, {"passed", k.passed}, {"detail", k.detail}});
    nlohmann::ordered_json result = {{"calibrated", serial},
                                     {"finger", a.finger + 1},
                                     {"files", {base + ".json", base + ".csv", base + ".html"}},
                                     {"compensator", host::CompensatorLabel(run.file)},
                                     {"operators_with_weight", run.fit.operators_used},
                                     {"residual_rms", run.file.quality.residual_rms},
                                     {"checks", checks},
                                     {"applied", a.apply}};
    if (run.file.simulation) {
      result["simulation"] = {{"actuator_unit", run.file.simulation->actuator_unit},
                              {"seed", run.file.simulation->seed},
                              {"plant_level", run.file.simulation->plant_level},
                              {"effects", run.file.simulation->effects}};
    }
    PrintJson(result);
  }
  return kExitOk;
}

}  // namespace palpa::cli
