// palpa calibrate: the thesis protocol on a rig (lab hardware by a rig file, or palpa-sim's rig),
// with a progress bar and time remaining, a journal to resume from, and the calibration file,
// raw data and an HTML report written to the output directory.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "calibrate_args.h"
#include "cli.h"
#include "palpa/calibration/board_rig.h"
#include "palpa/calibration/session.h"
#include "progress_bar.h"
#include "sim_options.h"

namespace palpa::cli {
namespace {

namespace cal = calibration;

void ShowProgress(ProgressBar& bar, const cal::Progress& p,
                  std::chrono::steady_clock::time_point start) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double left = p.done > 0 ? elapsed * (p.total - p.done) / p.done : 0;
  char text[96];
  std::snprintf(text, sizeof(text), "%3d/%d  %s left  %-48.48s", p.done, p.total,
                p.done > 0 ? (std::to_string(static_cast<int>(left / 60)) + "m" +
                              std::to_string(static_cast<int>(left) % 60) + "s")
                                 .c_str()
                           : "--",
                p.step.c_str());
  bar.Show(p.done, p.total, text);
}

/// The board and the rig on it: palpa-sim serving both, or a rig file and --device.
struct OpenedRig {
  std::optional<cal::BoardRig> rig;
  host::Device* device = nullptr;
  /// The simulator's board, closed on a signal (--device: Context's); gone before the rig is.
  std::optional<ClosedOnSignal> closed_on_signal;
  std::string serial;
};

/// Opens the rig and reads the finger's actuator serial; an exit code when it cannot.
int OpenRig(Context& c, const CalibrateArgs& a, OpenedRig& r) {
  std::optional<cal::RigDescription> description;
  if (a.rig == "sim") {
    if (!c.device_uri.empty() && c.device_uri.rfind("sim", 0) != 0) {
      return Usage("calibrate", "--rig sim goes with a simulated device (--device sim[:CONFIG])");
    }
    const std::string config = c.device_uri.size() > 4 ? c.device_uri.substr(4) : "thesis-5finger";
    // Fingers numbered as the command line numbers them.
    auto opened = cal::OpenSimulatedRig(config, a.finger, a.speed, a.plant, 1);
    if (!opened.ok()) return Fail("calibrate", opened.status, opened.message, kExitConnect);
    r.rig = std::move(opened.value);
    r.device = r.rig->device;
    r.closed_on_signal.emplace(r.device);
  } else {
    auto loaded = cal::LoadRigDescription(a.rig);
    if (!loaded.ok()) return Usage("calibrate", "--rig " + loaded.message);
    description = std::move(loaded.value);
    r.device = c.Device();
    if (r.device == nullptr) return kExitConnect;
  }
  const host::Result<std::string> serial =
      cal::ReadActuatorSerial(*r.device, static_cast<uint8_t>(a.finger));
  if (serial.status == protocol::Status::kInvalidArgument)
    return Usage("calibrate", "--finger " + std::to_string(a.finger + 1) + ": " + serial.message);
  if (serial.status == protocol::Status::kBadValue) {
    return Fail("calibrate", serial.status, serial.message + "; set it with palpa config set");
  }
  if (!serial.ok()) return Fail("calibrate", serial.status, serial.message);
  r.serial = serial.value;
  if (!r.rig) {
    auto opened = cal::OpenBoardRig(*r.device, *description);
    if (!opened.ok()) return Fail("calibrate", opened.status, opened.message, kExitConnect);
    r.rig = std::move(opened.value);
  }
  return kExitOk;
}

/// `simulation`: the simulator's own account of its plant (--rig sim), else null.
cal::SessionOptions SessionOptionsOf(const CalibrateArgs& a,
                                     const host::SimulatedPlant* simulation) {
  cal::SessionOptions s;
  s.finger = static_cast<uint8_t>(a.finger);
  cal::ProtocolOptions& options = s.protocol;
  options = a.quick ? cal::QuickProtocol() : cal::ProtocolOptions{};
  if (a.protocol == "adaptive") options.map_protocol = cal::MapProtocol::kAdaptive;
  options.compensator = a.compensator;
  if (a.operators > 0) options.compensator_operators = a.operators;
  options.adaptive.target_error = a.target_pct / 100;
  options.adaptive.max_cycles = a.max_cycles;
  options.adaptive.min_cycles = std::min(options.adaptive.min_cycles, a.max_cycles);
  s.out_dir = a.out;
  s.resume = a.resume;
  s.previous = a.previous;
  s.allow_fallback = a.allow_fallback;
  if (simulation != nullptr) s.simulation = *simulation;
  s.journal_not_saved = [](const std::string& why) {
    std::fprintf(stderr, "\npalpa calibrate: journal not saved (%s): a stopped run cannot resume\n",
                 why.c_str());
  };
  return s;
}

/// What the sweep allows, said before anything runs; a compensator it cannot fit is refused
/// now rather than after the whole run.
int AnnounceSweep(const CalibrateArgs& a, const cal::Session& session) {
  const cal::SweepCapacity sweep = session.Sweep();
  std::fprintf(TextOut(), "hysteresis sweep%s: %s\n", a.quick ? " (--quick)" : "",
               sweep.Describe(a.compensator).c_str());
  std::fflush(TextOut());
  const std::string why = sweep.Refusal(a.compensator);
  if (why.empty()) return kExitOk;
  if (!session.CheckSweep().ok()) {
    return Usage("calibrate", "--compensator: " + why +
                                  "; ask for fewer operators, or --allow-fallback to keep the "
                                  "static inverse alone");
  }
  std::fprintf(TextOut(),
               "  note: %s; with --allow-fallback the file will have the static inverse alone\n",
               why.c_str());
  return kExitOk;
}

/// The output directory, the journal to resume and the previous calibration, in that order.
int PrepareSession(const CalibrateArgs& a, cal::Session& session) {
  if (const host::Outcome o = session.OpenOutput(); !o.ok())
    return Fail("calibrate", o.status, o.message);
  if (a.resume) {
    const host::Outcome o = session.Resume();
    if (o.status == protocol::Status::kNotFound)
      return Usage("calibrate", "--resume: " + o.message);
    if (!o.ok()) return Usage("calibrate", "--resume: " + o.message + " (nothing was started)");
  }
  const host::Outcome previous = session.LoadPrevious();
  if (previous.status == protocol::Status::kInvalidArgument)
    return Usage("calibrate", "--previous " + previous.message);
  if (!previous.ok()) return Usage("calibrate", previous.message);
  return kExitOk;
}

/// The run and its files; the journal is kept when it stops, for --resume.
int RunSession(cal::Session& session) {
  const std::string journal = session.base() + ".journal.json";
  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar;
  const host::Outcome run =
      session.Run([&](const cal::Progress& p) { ShowProgress(bar, p, start); });
  bar.End();
  if (session.stopped()) {
    return Fail("calibrate", run.status,
                "stopped: " + run.message +
                    "\nThe stage was retracted and the board vented. What was finished is in " +
                    journal + "; run again with --resume to continue.");
  }
  if (!run.ok()) {
    return Fail("calibrate", run.status,
                run.message + "\nNothing was written; the measurements are kept in " + journal +
                    ": run again with --resume and another --compensator, or with "
                    "--allow-fallback to keep the static inverse alone.");
  }
  if (const host::Outcome o = session.Write(); !o.ok())
    return Fail("calibrate", o.status, o.message);
  return kExitOk;
}

/// The files, the fits and the detectors' verdicts, as a person reads them.
void PrintResult(const CalibrateArgs& a, const cal::Session& session) {
  const cal::CalibrationRun& run = session.result();
  const std::string base = session.base();
  // The plant as the simulator said it runs it (the file records the same).
  const std::optional<host::SimulatedPlant>& simulation = run.file.simulation;
  std::fprintf(TextOut(), "calibrated %s (finger %d%s): %s.json, %s.csv, %s.html\n",
               session.serial().c_str(), a.finger + 1,
               simulation ? (", " + DescribeSimulatedPlant(*simulation)).c_str() : "", base.c_str(),
               base.c_str(), base.c_str());
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
                 session.jamming() ? "mN/mm" : "µm");
  }
}

}  // namespace

int CmdCalibrate(Context& c, const std::vector<std::string>& args) {
  CalibrateArgs a;
  if (const int rc = ParseCalibrateArgs(args, a); rc != kExitOk) return rc;
  if (const int rc = CheckCalibrateArgs(a); rc != kExitOk) return rc;
  OpenedRig opened;
  if (const int rc = OpenRig(c, a, opened); rc != kExitOk) return rc;
  host::Device& device = *opened.device;
  const bool jamming = device.info().fingers[a.finger].kind == protocol::FingerKind::kJamming;
  const host::SimulatedPlant* simulation =
      opened.rig->simulated() ? &opened.rig->simulation : nullptr;
  cal::Session session(opened.rig->rig(), opened.serial, device.info().board_id, jamming,
                       SessionOptionsOf(a, simulation));
  if (const int rc = AnnounceSweep(a, session); rc != kExitOk) return rc;
  if (const int rc = PrepareSession(a, session); rc != kExitOk) return rc;
  if (const int rc = RunSession(session); rc != kExitOk) return rc;
  PrintResult(a, session);
  if (a.apply) {
    const host::Outcome o =
        device.ApplyCalibration(static_cast<uint8_t>(a.finger), session.result().file);
    if (!o.ok()) return Report(c, o, "apply calibration");
    std::fprintf(TextOut(),
                 "  applied to finger %d (static inverse, compensator, regulator correction%s)\n",
                 a.finger + 1, session.result().file.recommended_bias_pa ? ", bias" : "");
  }
  if (c.json) PrintJson(session.Summary(a.apply, 1));
  return kExitOk;
}

const Command kCalibrateCommand{
    "calibrate",
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
    "settings (a 10 kPa sweep; the run says first which compensators it can fit).\n"
    "--compensator: the model fitted, pi or api with N operators (default 16, 8 with --quick,\n"
    "fewer when the sweep tells fewer apart); auto (default) fits both and keeps api where it\n"
    "leaves at most 3/4 of pi's residual. A model that cannot be fitted is an error (nothing\n"
    "written) unless --allow-fallback keeps the static inverse alone. --apply uploads the\n"
    "result to the finger (one staged change).",
    CmdCalibrate};

}  // namespace palpa::cli
