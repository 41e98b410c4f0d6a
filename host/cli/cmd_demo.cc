// palpa demo: a simulated thesis-5finger board plays the thesis's discrimination stimuli on the
// nominal curves, then again once its pneumatic fingers are calibrated and compensated; each step
// prints target against achieved (the simulator's truth), settling time and latency.
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "cli.h"
#include "demo_calibration.h"
#include "demo_pass.h"
#include "demo_truth.h"
#include "palpa/host/file_write.h"
#include "palpa/host/stimulus_set.h"
#include "palpa/host/svg_chart.h"

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
  std::string error;
  std::optional<host::StimulusSet> set = host::LoadStimulusSet(name, &error);
  if (!set) {
    Usage("demo", "--stimuli " + error);
    return false;
  }
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

int CmdDemo(Context& c, const std::vector<std::string>& args) {
  // The demo always runs on a simulator of its own, whatever --device says.
  DemoArgs a;
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
  std::optional<host::StimulusSet> pneumatic_set, jamming_set;
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
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", a.speed);
  std::fprintf(
      TextOut(),
      "palpa demo: starting a simulated thesis-5finger board (plant level 3: regulators with "
      "static errors,\n"
      "hysteretic fingers, real sensors), running %sx faster than real time\n",
      speed_text);
  std::string truth_address, error;
  auto transport = host::LaunchSim(kConfig, {"--speed", speed_text, "--truth-every-ms", "10"},
                                   &truth_address, &error);
  if (!transport.ok()) return Fail("demo", transport.status, error, kExitConnect);
  // Nominal curves in the first pass whatever calibrations this user keeps for PN-1 .. PN-5.
  host::DeviceOptions options;
  options.use_calibrations = false;
  options.number_from = 1;
  options.levels = host::LevelTablesFor(&*pneumatic_set, &*jamming_set);
  auto device = host::Device::Attach(std::move(transport.value), options, &error);
  if (!device.ok()) return Fail("demo", device.status, error, kExitConnect);
  host::Device& d = *device.value;
  const ClosedOnSignal closed_on_signal(&d);
  TruthReader truth;
  if (!truth.Connect(truth_address)) {
    return Fail("demo", protocol::Status::kUnavailable,
                "cannot read the simulator's truth channel at " + truth_address, kExitConnect);
  }
  const PneumaticFingers fingers = FindPneumatic(d);
  std::optional<std::vector<host::CalibrationFile>> files;
  if (!a.calibration_dir.empty()) {
    files = ReadCalibrationDir(fingers, a.calibration_dir);
    if (!files) return kExitFailed;
  }
  std::vector<Step> pneumatic, all;
  for (const host::Stimulus& st : pneumatic_set->stimuli)
    pneumatic.push_back({st.levels, false, host::LevelNames(*pneumatic_set, st)});
  all = pneumatic;
  for (const host::Stimulus& st : jamming_set->stimuli)
    all.push_back({st.levels, true, host::LevelNames(*jamming_set, st)});
  auto describe = [](const host::StimulusSet& set) {
    std::string levels;
    for (const host::StimulusLevel& l : set.levels) {
      char v[16];
      std::snprintf(v, sizeof(v), "%g", l.kpa);
      levels += (levels.empty() ? "" : "/") + std::string(v);
    }
    return set.name + ": " + std::to_string(set.stimuli.size()) + " of " + levels + " kPa on " +
           std::to_string(set.fingers) + " fingers";
  };
  std::fprintf(
      TextOut(),
      "stimuli: %s; %s at %g kPa bias\n"
      "(a tumour: one finger or two adjacent fingers stiffer than the rest), each played on all\n"
      "its fingers at once (the thesis's multi-finger condition). Deformation is the bare film's\n"
      "in mm, as thesis Table 5-4 measured it without the top silicone layer (the simulator\n"
      "models the film alone); stiffness in N/mm.\n\n"
      "pass 1: the nominal thesis curves, no hysteresis compensation (the `none` compensator)\n",
      describe(*pneumatic_set).c_str(), describe(*jamming_set).c_str(), jamming_set->bias_kpa);
  const host::LevelTables& levels = options.levels;
  std::vector<host::Series> targets(d.info().finger_count);
  PassFigures nominal, calibrated;
  if (!PlaySteps(d, truth, levels, all, targets, nominal)) return kExitFailed;
  const double first_pass_end_s = truth.now_s();
  std::vector<host::Series> second_targets(d.info().finger_count);
  double second_pass_s = 0;
  std::string compensator;
  if (a.calibrate) {
    if (!files) files = CalibrateOnSimulatedRigs(kConfig, fingers, a.speed);
    if (!files) return kExitFailed;
    if (!a.calibration_dir.empty())
      std::fprintf(TextOut(), "\ncalibrations from %s\n", a.calibration_dir.c_str());
    if (!ApplyCalibrations(d, fingers, *files, &compensator)) return kExitFailed;
    std::fprintf(TextOut(),
                 "\npass 2: the pneumatic stimuli again, each finger on its own calibration and "
                 "compensated\n");
    second_pass_s = truth.now_s();
    if (!PlaySteps(d, truth, levels, pneumatic, second_targets, calibrated)) return kExitFailed;
  }
  // The chart leaves out the board time spent calibrating (the fingers held still meanwhile):
  // the second pass is drawn 2 s after the first, and the gap is marked.
  const double cut_s = a.calibrate ? second_pass_s - first_pass_end_s - 2 : 0;
  auto drawn_at = [&](double t) { return t >= second_pass_s && a.calibrate ? t - cut_s : t; };
  // Deformation (mm) and stiffness (N/mm) are different quantities: a panel each.
  host::Chart pneumatic_panel, jamming_panel;
  pneumatic_panel.y_label = "deformation (mm), fingers 1-3";
  jamming_panel.y_label = "stiffness (N/mm), fingers 4-5";
  pneumatic_panel.x_label = jamming_panel.x_label = "board time (s)";
  pneumatic_panel.width = jamming_panel.width = 1100;
  pneumatic_panel.height = 380;
  jamming_panel.height = 300;
  if (a.calibrate) {
    char label[96];
    std::snprintf(label, sizeof(label), "%.0f s of calibration left out", cut_s);
    for (host::Chart* panel : {&pneumatic_panel, &jamming_panel})
      panel->markers.push_back({first_pass_end_s, first_pass_end_s + 2, label});
  }
  const auto samples = truth.All();
  const char* names[] = {"finger 1", "finger 2", "finger 3", "finger 4", "finger 5"};
  const char* colours[] = {"#2471a3", "#c0392b", "#229954", "#7d3c98", "#d68910"};
  for (size_t f = 0; f < 5; ++f) {
    host::Chart& panel = f < 3 ? pneumatic_panel : jamming_panel;
    host::Series trace{names[f], {}, colours[f], false, false};
    for (size_t i = 0; i < samples.size(); i += 5) {
      const double t = samples[i].t_s;
      if (a.calibrate && t > first_pass_end_s && t < second_pass_s) continue;
      trace.points.push_back({drawn_at(t), samples[i].outputs[f]});
    }
    panel.series.push_back(trace);
  }
  for (size_t f = 0; f < 5; ++f) {  // the targets, dashed in the finger's colour
    host::Chart& panel = f < 3 ? pneumatic_panel : jamming_panel;
    targets[f].name = std::string("target ") + std::to_string(f + 1);
    targets[f].color = colours[f];
    targets[f].dashed = true;
    panel.series.push_back(targets[f]);
    if (second_targets[f].points.empty()) continue;
    for (auto& point : second_targets[f].points) point.first = drawn_at(point.first);
    second_targets[f].color = colours[f];  // unnamed: the legend lists it once
    second_targets[f].dashed = true;
    panel.series.push_back(second_targets[f]);
  }
  std::string title =
      "palpa demo: thesis stimuli on a simulated thesis-5finger board (true outputs, targets "
      "dashed)";
  if (a.calibrate) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "palpa demo: thesis stimuli, nominal, then calibrated from %.0f s (true "
                  "outputs, targets dashed)",
                  drawn_at(second_pass_s));
    title = text;
  }
  d.EStop();
  if (!host::WriteFileWhole(a.out, host::RenderSvgPanels({pneumatic_panel, jamming_panel}, title),
                            &error)) {
    return Fail("demo", protocol::Status::kIoError, error);
  }
  PrintSummary(nominal, a.calibrate ? &calibrated : nullptr, compensator);
  if (c.json) {
    PrintJson({{"nominal", PassJson(nominal)},
               {"calibrated", a.calibrate ? PassJson(calibrated) : nlohmann::ordered_json(nullptr)},
               {"compensator", compensator},
               {"calibration_left_out_s", cut_s},
               {"chart", a.out}});
  } else {
    std::printf("traces plotted to %s\n", a.out.c_str());
  }
  return kExitOk;
}

}  // namespace palpa::cli
