// palpa demo: a simulated thesis-5finger board plays the thesis's discrimination stimuli on the
// nominal curves, then again once its pneumatic fingers are calibrated and compensated; each step
// prints target against achieved (the simulator's truth), settling time and latency.
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "cli.h"
#include "demo_calibration.h"
#include "demo_pass.h"
#include "demo_stimuli.h"
#include "demo_truth.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace palpa::cli {
namespace {

constexpr const char* kConfig = "thesis-5finger";

struct DemoArgs {
  std::string out = "palpa-demo.svg";
  double speed = 4;
  bool calibrate = true;        ///< the second, compensated pass
  std::string calibration_dir;  ///< its calibrations from files instead of the simulated rig
};

}  // namespace

int CmdDemo(Context& c, const std::vector<std::string>& args) {
  (void)c;  // the demo always runs on a simulator of its own, whatever --device says
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
    } else if (args[i] == "--nominal-only") {
      a.calibrate = false;
    } else {
      return Usage("demo", "unexpected argument '" + args[i] + "'");
    }
  }
  if (!a.calibrate && !a.calibration_dir.empty())
    return Usage("demo", "--nominal-only and --calibration exclude each other");
  // Checked before the run, not after it: the chart is written at the end.
  const std::filesystem::path chart_dir = std::filesystem::path(a.out).parent_path();
  const std::string dir = chart_dir.empty() ? "." : chart_dir.string();
  if (!std::filesystem::is_directory(dir) || access(dir.c_str(), W_OK) != 0) {
    return Usage("demo",
                 "--out " + a.out + ": " + dir + " is not a directory this user can write to");
  }
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", a.speed);
  std::printf(
      "palpa demo: starting a simulated thesis-5finger board (plant level 3: regulators with "
      "static errors,\n"
      "hysteretic fingers, real sensors), running %sx faster than real time\n",
      speed_text);
  std::string truth_address, error;
  auto transport = host::LaunchSim(kConfig, {"--speed", speed_text, "--truth-every-ms", "10"},
                                   &truth_address, &error);
  if (!transport.ok()) {
    std::fprintf(stderr, "palpa demo: %s\n", error.c_str());
    return kExitConnect;
  }
  // Nominal curves in the first pass whatever calibrations this user keeps for PN-1 .. PN-5.
  host::DeviceOptions options;
  options.use_calibrations = false;
  auto device = host::Device::Attach(std::move(transport.value), options, &error);
  if (!device.ok()) {
    std::fprintf(stderr, "palpa demo: %s\n", error.c_str());
    return kExitConnect;
  }
  host::Device& d = *device.value;
  TruthReader truth;
  if (!truth.Connect(truth_address)) {
    std::fprintf(stderr, "palpa demo: cannot read the simulator's truth channel at %s\n",
                 truth_address.c_str());
    return kExitConnect;
  }
  const PneumaticFingers fingers = FindPneumatic(d);
  std::optional<std::vector<host::CalibrationFile>> files;
  if (!a.calibration_dir.empty()) {
    files = ReadCalibrationDir(fingers, a.calibration_dir);
    if (!files) return kExitFailed;
  }
  std::vector<Step> pneumatic, all;
  for (const auto& combo : TumourCombinations(3, 3)) pneumatic.push_back({combo, false});
  all = pneumatic;
  for (const auto& combo : TumourCombinations(2, 3)) all.push_back({combo, true});
  std::printf(
      "stimuli: %zu three-finger pneumatic combinations of 0/10/30 kPa, %zu two-finger jamming "
      "combinations\n"
      "of 0/-10/-100 kPa at 20 kPa bias (a tumour: one finger or two adjacent fingers stiffer than "
      "the rest)\n\n"
      "pass 1: the nominal thesis curves, no hysteresis compensation (the `none` compensator)\n",
      pneumatic.size(), all.size() - pneumatic.size());
  std::vector<host::Series> targets(d.info().finger_count);
  PassFigures nominal, calibrated;
  if (!PlaySteps(d, truth, all, targets, nominal)) return kExitFailed;
  const double first_pass_end_s = truth.now_s();
  std::vector<host::Series> second_targets(d.info().finger_count);
  double second_pass_s = 0;
  std::string compensator;
  if (a.calibrate) {
    if (!files) files = CalibrateOnSimulatedRigs(kConfig, fingers, a.speed);
    if (!files) return kExitFailed;
    if (!a.calibration_dir.empty())
      std::printf("\ncalibrations from %s\n", a.calibration_dir.c_str());
    if (!ApplyCalibrations(d, fingers, *files, &compensator)) return kExitFailed;
    std::printf(
        "\npass 2: the pneumatic stimuli again, each finger on its own calibration and "
        "compensated\n");
    second_pass_s = truth.now_s();
    if (!PlaySteps(d, truth, pneumatic, second_targets, calibrated)) return kExitFailed;
  }
  // The chart leaves out the board time spent calibrating (the fingers held still meanwhile):
  // the second pass is drawn 2 s after the first.
  const double cut_s = a.calibrate ? second_pass_s - first_pass_end_s - 2 : 0;
  auto drawn_at = [&](double t) { return t >= second_pass_s && a.calibrate ? t - cut_s : t; };
  host::Chart chart;
  chart.title = "palpa demo: thesis stimuli on a simulated thesis-5finger board (true outputs)";
  if (a.calibrate) {
    char title[160];
    std::snprintf(title, sizeof(title),
                  "palpa demo: thesis stimuli, nominal, then calibrated from %.0f s (true outputs; "
                  "%.0f s of calibration left out)",
                  drawn_at(second_pass_s), cut_s);
    chart.title = title;
  }
  chart.x_label = "board time (s)";
  chart.y_label = "deformation (mm), fingers 1-3 / stiffness (N/mm), fingers 4-5";
  const auto samples = truth.All();
  const char* names[] = {"finger 1 (mm)", "finger 2 (mm)", "finger 3 (mm)", "finger 4 (N/mm)",
                         "finger 5 (N/mm)"};
  const char* colours[] = {"#2471a3", "#c0392b", "#229954", "#7d3c98", "#d68910"};
  for (size_t f = 0; f < 5; ++f) {
    host::Series trace{names[f], {}, colours[f], false, false};
    for (size_t i = 0; i < samples.size(); i += 5) {
      const double t = samples[i].t_s;
      if (a.calibrate && t > first_pass_end_s && t < second_pass_s) continue;
      trace.points.push_back({drawn_at(t), samples[i].outputs[f]});
    }
    chart.series.push_back(trace);
  }
  for (size_t f = 0; f < 5; ++f) {  // the targets, dashed in the finger's colour
    targets[f].name = std::string("target ") + std::to_string(f + 1);
    targets[f].color = colours[f];
    targets[f].dashed = true;
    chart.series.push_back(targets[f]);
    if (second_targets[f].points.empty()) continue;
    for (auto& point : second_targets[f].points) point.first = drawn_at(point.first);
    second_targets[f].color = colours[f];  // unnamed: the legend lists it once
    second_targets[f].dashed = true;
    chart.series.push_back(second_targets[f]);
  }
  chart.width = 1100;
  d.EStop();
  if (!host::WriteFileWhole(a.out, host::RenderSvg(chart), &error)) {
    std::fprintf(stderr, "palpa demo: %s\n", error.c_str());
    return kExitFailed;
  }
  PrintSummary(nominal, a.calibrate ? &calibrated : nullptr, compensator);
  std::printf("traces plotted to %s\n", a.out.c_str());
  return kExitOk;
}

}  // namespace palpa::cli
