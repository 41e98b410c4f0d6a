// palpa demo: a simulated thesis-5finger board plays the thesis's discrimination stimuli on the
// nominal curves, then again once its pneumatic fingers are calibrated and compensated; each step
// prints target against achieved (the simulator's truth), settling time and latency.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli.h"
#include "demo_calibration.h"
#include "demo_chart.h"
#include "demo_pass.h"
#include "palpa/host/file_write.h"
#include "palpa/host/sim_truth.h"
#include "palpa/host/stimulus_set.h"

namespace palpa::cli {
namespace {

constexpr const char* kConfig = "thesis-5finger";

struct DemoArgs {
  std::string out = "palpa-demo.svg";
  double speed = 4;
  bool calibrate = true;             ///< the second, compensated pass
  std::string calibration_dir;       ///< its calibrations from files instead of the simulated rig
  std::vector<std::string> stimuli;  ///< sets by name or file; the full thesis sets by default
};

/// A stimulus set by name or file, for the fingers the demo's board has of its kind; false
/// (printed) when it cannot be read or does not fit them.
bool LoadSet(const std::string& name, std::optional<host::StimulusSet>& pneumatic,
             std::optional<host::StimulusSet>& jamming) {
  host::Result<host::StimulusSet> loaded = host::LoadStimulusSet(name);
  if (!loaded.ok()) {
    Usage("demo", "--stimuli " + loaded.message);
    return false;
  }
  std::optional<host::StimulusSet> set = std::move(loaded.value);
  const bool is_jamming = set->fingers_kind == host::StimulusFingers::kJamming;
  const int wanted = is_jamming ? 2 : 3;  // thesis-5finger: fingers 1-3 pneumatic, 4-5 jamming
  if (set->fingers != wanted) {
    Usage("demo", "--stimuli " + name + ": a set for " + std::to_string(set->fingers) + " " +
                      (is_jamming ? "jamming" : "pneumatic") + " fingers; the demo's board has " +
                      std::to_string(wanted));
    return false;
  }
  (is_jamming ? jamming : pneumatic) = std::move(set);
  return true;
}

}  // namespace

/// A pass's figures for --json.
nlohmann::ordered_json PassJson(const PassFigures& f) {
  return {{"pneumatic_largest_error_pct", f.worst_pct[0]},
          {"pneumatic_rms_error_pct", f.Rms(0)},
          {"jamming_largest_error_pct", f.count[1] > 0 ? nlohmann::ordered_json(f.worst_pct[1])
                                                       : nlohmann::ordered_json(nullptr)},
          {"level1_from_above_minus_below_um",
           f.n_above > 0 && f.n_below > 0
               ? nlohmann::ordered_json(1000 *
                                        (f.l1_from_above / f.n_above - f.l1_from_below / f.n_below))
               : nlohmann::ordered_json(nullptr)}};
}

namespace {

/// The command line and the stimulus sets it names, all checked before anything starts: a usage
/// error's exit code, else kExitOk.
int ParseDemoArgs(const std::vector<std::string>& args, DemoArgs& a,
                  std::optional<host::StimulusSet>& pneumatic_set,
                  std::optional<host::StimulusSet>& jamming_set) {
  for (size_t i = 0; i < args.size(); ++i) {
    const bool has_value = i + 1 < args.size();
    if (args[i] == "--out") {
      if (!has_value) return Usage("demo", "--out needs a file name for the chart");
      a.out = args[++i];
    } else if (args[i] == "--speed") {
      // Faster, the board's 100 ms host-silence timeout is a few ms of real time: too short for
      // a host sharing its cores with the simulators.
      if (!has_value || !ParseNumber(args[++i], a.speed) || a.speed < 0.1 || a.speed > 10)
        return Usage("demo", "--speed needs a number from 0.1 to 10");
    } else if (args[i] == "--calibration") {
      if (!has_value) return Usage("demo", "--calibration needs a directory of calibration files");
      a.calibration_dir = args[++i];
      if (!std::filesystem::is_directory(a.calibration_dir))
        return Usage("demo", "--calibration " + a.calibration_dir + ": not a directory");
    } else if (args[i] == "--stimuli") {
      if (!has_value) return Usage("demo", "--stimuli needs a set's name or a stimulus-set file");
      a.stimuli.push_back(args[++i]);
    } else if (args[i] == "--nominal-only") {
      a.calibrate = false;
    } else {
      return Usage("demo", "unexpected argument '" + args[i] + "'");
    }
  }
  if (!a.calibrate && !a.calibration_dir.empty())
    return Usage("demo", "--nominal-only and --calibration exclude each other");
  const std::string extension = std::filesystem::path(a.out).extension().string();
  if (extension != ".svg" && extension != ".SVG") {
    return Usage("demo",
                 "--out " + a.out + ": the chart is an SVG drawing; give a name ending in .svg");
  }
  for (const std::string& name : a.stimuli) {
    if (!LoadSet(name, pneumatic_set, jamming_set)) return kExitUsage;
  }
  if (!pneumatic_set && !LoadSet("thesis-pneumatic-18", pneumatic_set, jamming_set))
    return kExitFailed;
  if (!jamming_set && !LoadSet("thesis-jamming-9", pneumatic_set, jamming_set)) return kExitFailed;
  // Checked before the run, not after it: the chart is written at the end.
  const std::filesystem::path chart_dir = std::filesystem::path(a.out).parent_path();
  const std::string dir = chart_dir.empty() ? "." : chart_dir.string();
  if (!std::filesystem::is_directory(dir) || access(dir.c_str(), W_OK) != 0) {
    return Usage("demo",
                 "--out " + a.out + ": " + dir + " is not a directory this user can write to");
  }
  return kExitOk;
}

/// The demo's own simulated board, its device on the nominal curves, and its truth channel.
struct DemoBoard {
  std::unique_ptr<host::Device> device;
  std::optional<ClosedOnSignal> closed_on_signal;
  host::TruthReader truth;
};

int StartBoard(const DemoArgs& a, const host::LevelTables& levels, DemoBoard& board) {
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", a.speed);
  std::fprintf(
      TextOut(),
      "palpa demo: starting a simulated thesis-5finger board (plant level 3: regulators with "
      "static errors,\n"
      "hysteretic fingers, real sensors), running %sx faster than real time\n",
      speed_text);
  std::string truth_address;
  auto transport =
      host::LaunchSim(kConfig, {"--speed", speed_text, "--truth-every-ms", "10"}, &truth_address);
  if (!transport.ok()) return Fail("demo", transport.status, transport.message, kExitConnect);
  // Nominal curves in the first pass whatever calibrations this user keeps for PN-1 .. PN-5.
  host::DeviceOptions options;
  options.use_calibrations = false;
  options.number_from = 1;
  options.levels = levels;
  auto device = host::Device::Attach(std::move(transport.value), options);
  if (!device.ok()) return Fail("demo", device.status, device.message, kExitConnect);
  board.device = std::move(device.value);
  board.closed_on_signal.emplace(board.device.get());
  if (!board.truth.Connect(truth_address)) {
    return Fail("demo", protocol::Status::kUnavailable,
                "cannot read the simulator's truth channel at " + truth_address, kExitConnect);
  }
  return kExitOk;
}

std::string DescribeSet(const host::StimulusSet& set) {
  std::string levels;
  for (const host::StimulusLevel& l : set.levels) {
    char v[16];
    std::snprintf(v, sizeof(v), "%g", l.kpa);
    levels += (levels.empty() ? "" : "/") + std::string(v);
  }
  return set.name + ": " + std::to_string(set.stimuli.size()) + " of " + levels + " kPa on " +
         std::to_string(set.fingers) + " fingers";
}

/// What the two passes measured, for the summary and --json.
struct DemoFigures {
  PassFigures nominal, calibrated;
  std::string compensator;
};

/// Pass 1 on the nominal curves; then (unless --nominal-only) the pneumatic fingers calibrated
/// on simulated rigs or from --calibration's files, and pass 2 on them. False (printed) when a
/// step fails.
bool PlayPasses(const DemoArgs& a, const host::StimulusSet& pneumatic_set,
                const host::StimulusSet& jamming_set, DemoBoard& board, DemoTraces& traces,
                DemoFigures& figures) {
  host::Device& d = *board.device;
  const PneumaticFingers fingers = FindPneumatic(d);
  std::optional<std::vector<host::CalibrationFile>> files;
  if (!a.calibration_dir.empty()) {
    files = ReadCalibrationDir(fingers, a.calibration_dir);
    if (!files) return false;
  }
  std::vector<Step> pneumatic, all;
  for (const host::Stimulus& st : pneumatic_set.stimuli)
    pneumatic.push_back({st.levels, false, host::LevelNames(pneumatic_set, st)});
  all = pneumatic;
  for (const host::Stimulus& st : jamming_set.stimuli)
    all.push_back({st.levels, true, host::LevelNames(jamming_set, st)});
  std::fprintf(
      TextOut(),
      "stimuli: %s; %s at %g kPa bias\n"
      "(a tumour: one finger or two adjacent fingers stiffer than the rest), each played on all\n"
      "its fingers at once (the thesis's multi-finger condition). Deformation is the bare film's\n"
      "in mm, as thesis Table 5-4 measured it without the top silicone layer (the simulator\n"
      "models the film alone); stiffness in N/mm.\n\n"
      "pass 1: the nominal thesis curves, no hysteresis compensation (the `none` compensator)\n",
      DescribeSet(pneumatic_set).c_str(), DescribeSet(jamming_set).c_str(), jamming_set.bias_kpa);
  const host::LevelTables levels = host::LevelTablesFor(&pneumatic_set, &jamming_set);
  traces.targets.assign(d.info().finger_count, {});
  traces.second.assign(d.info().finger_count, {});
  if (!PlaySteps(d, board.truth, levels, all, traces.targets, figures.nominal)) return false;
  traces.first_pass_end_s = board.truth.now_s();
  traces.calibrated = a.calibrate;
  if (!a.calibrate) return true;
  if (!files) files = CalibrateOnSimulatedRigs(kConfig, fingers, a.speed);
  if (!files) return false;
  if (!a.calibration_dir.empty())
    std::fprintf(TextOut(), "\ncalibrations from %s\n", a.calibration_dir.c_str());
  if (!ApplyCalibrations(d, fingers, *files, &figures.compensator)) return false;
  std::fprintf(TextOut(),
               "\npass 2: the pneumatic stimuli again, each finger on its own calibration and "
               "compensated\n");
  traces.second_pass_s = board.truth.now_s();
  return PlaySteps(d, board.truth, levels, pneumatic, traces.second, figures.calibrated);
}

}  // namespace

int CmdDemo(Context& c, const std::vector<std::string>& args) {
  // The demo always runs on a simulator of its own, whatever --device says.
  DemoArgs a;
  std::optional<host::StimulusSet> pneumatic_set, jamming_set;
  if (const int rc = ParseDemoArgs(args, a, pneumatic_set, jamming_set); rc != kExitOk) return rc;
  DemoBoard board;
  const host::LevelTables levels = host::LevelTablesFor(&*pneumatic_set, &*jamming_set);
  if (const int rc = StartBoard(a, levels, board); rc != kExitOk) return rc;
  DemoTraces traces;
  DemoFigures figures;
  if (!PlayPasses(a, *pneumatic_set, *jamming_set, board, traces, figures)) return kExitFailed;
  traces.samples = board.truth.All();
  const std::string svg = DemoChartSvg(traces);
  board.device->EStop();
  if (const host::Outcome o = host::WriteFileWhole(a.out, svg); !o.ok())
    return Fail("demo", o.status, o.message);
  PrintSummary(figures.nominal, a.calibrate ? &figures.calibrated : nullptr, figures.compensator);
  if (c.json) {
    PrintJson({{"nominal", PassJson(figures.nominal)},
               {"calibrated",
                a.calibrate ? PassJson(figures.calibrated) : nlohmann::ordered_json(nullptr)},
               {"compensator", figures.compensator},
               {"calibration_left_out_s", traces.CutS()},
               {"chart", a.out}});
  } else {
    std::printf("traces plotted to %s\n", a.out.c_str());
  }
  return kExitOk;
}

const Command kDemoCommand{
    "demo",
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
    "first pass. --speed X: 0.1-10, default 4.",
    CmdDemo};

}  // namespace palpa::cli
