// palpa render: a scene played to the board from a recorded trajectory, live status on the
// terminal, and a record of what each finger touched and was asked, with an SVG of the path.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "cli.h"
#include "palpa/host/file_write.h"
#include "palpa/host/scene.h"
#include "palpa/host/scene_svg.h"

namespace palpa::cli {
namespace {

struct RenderOptions {
  std::string scene, input, record;
};

host::Result<RenderOptions> Options(const std::vector<std::string>& args) {
  RenderOptions o;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--input" || args[i] == "--record") {
      const auto value = OptionValue(args, i);
      if (!value.ok()) return value.outcome();
      (args[i] == "--input" ? o.input : o.record) = value.value;
      ++i;
    } else if (args[i].rfind("--", 0) == 0 || !o.scene.empty()) {
      return {protocol::Status::kInvalidArgument, "unexpected argument " + args[i]};
    } else {
      o.scene = args[i];
    }
  }
  if (o.scene.empty() || o.input.empty())
    return {protocol::Status::kInvalidArgument, "a SCENE file and --input TRAJECTORY.csv"};
  return o;
}

/// "OUT" → "OUT.svg" beside it (an .csv ending replaced).
std::string SvgPath(const std::string& record) {
  const size_t dot = record.rfind(".csv");
  return (dot != std::string::npos && dot + 4 == record.size() ? record.substr(0, dot) : record) +
         ".svg";
}

int CmdRender(Context& c, const std::vector<std::string>& args) {
  const std::string cmd = "render";
  const auto options = Options(args);
  if (!options.ok()) return Usage(cmd, options.message);
  const RenderOptions& o = options.value;
  const auto spec = host::LoadScene(o.scene);
  if (!spec.ok()) return Fail(cmd, spec.status, spec.message, kExitUsage);
  const auto samples = host::LoadTrajectory(o.input);
  if (!samples.ok()) return Fail(cmd, samples.status, samples.message, kExitUsage);
  host::Device* device = c.Device();
  if (device == nullptr) return kExitConnect;
  auto scene = host::Scene::Open(spec.value, *device);
  if (!scene.ok()) return Fail(cmd, scene.status, scene.message, kExitUsage);
  // The board's time of the latest telemetry, for the record (one clock for every row).
  std::atomic<uint64_t> board_us{0};
  const int subscription = device->Subscribe([&](const host::TelemetryFrame& f) {
    const auto& t = f.telemetry;
    board_us = t.first_sample_us + uint64_t{t.tick_count - 1u} * t.sample_interval_us;
  });
  const bool live = !JsonOutput() && isatty(fileno(stdout));
  std::string csv = "time_s,x_mm,y_mm,force_n,board_time_us";
  for (size_t f = 0; f < spec.value.board_fingers.size(); ++f) {
    const std::string n = std::to_string(spec.value.board_fingers[f] + 1);
    csv += ",finger" + n + "_touching,finger" + n + "_value,finger" + n + "_target";
  }
  csv += "\n";
  std::vector<std::pair<double, double>> path;
  const PollsInterruption polls;
  // The trajectory's own pace on the board's clock: a simulator running X times faster than
  // real time (palpa-sim --speed X) takes the samples X times sooner.
  const double scale = device->info().time_scale > 0 ? device->info().time_scale : 1.0;
  const auto start = std::chrono::steady_clock::now();
  const double t0 = samples.value.front().time_s;
  size_t fed = 0;
  for (const host::SceneInput& s : samples.value) {
    if (Interrupted()) break;
    std::this_thread::sleep_until(start + std::chrono::duration<double>((s.time_s - t0) / scale));
    const auto renders = scene.value->Feed(s);
    if (!renders.ok()) {
      device->Unsubscribe(subscription);
      return Fail(cmd, renders.status, renders.message);
    }
    ++fed;
    path.emplace_back(s.x_mm, s.y_mm);
    char row[160];
    std::snprintf(row, sizeof(row), "%.6f,%.4f,%.4f,%.4f,%llu", s.time_s, s.x_mm, s.y_mm, s.force_n,
                  static_cast<unsigned long long>(board_us.load()));
    csv += row;
    std::string status;
    for (const host::FingerRender& r : renders.value) {
      std::snprintf(row, sizeof(row), ",%d,%.6g,%.6g", r.touching ? 1 : 0, r.value,
                    r.mapped.target / 1000.0);
      csv += row;
      std::snprintf(row, sizeof(row), "  %5.3f", r.mapped.target / 1000.0);
      status += row;
    }
    csv += "\n";
    if (live) {
      std::printf("\r%7.3f s  x %6.1f  y %6.1f mm  %4.2f N  targets%s", s.time_s, s.x_mm, s.y_mm,
                  s.force_n, status.c_str());
      std::fflush(stdout);
    }
  }
  device->Unsubscribe(subscription);
  if (live) std::printf("\n");
  if (!o.record.empty()) {
    // The fingers where the pass ended (where it started, when interrupted before any sample).
    const host::SceneInput& end = fed > 0 ? samples.value[fed - 1] : samples.value.front();
    const host::SceneRenderer& r = scene.value->renderer();
    const std::string svg = host::SceneSvg(r.tissue(), r.layout(), end.x_mm, end.y_mm, path,
                                           spec.value.name + " — " + o.input);
    for (const auto& [file, text] : {std::pair{o.record, csv}, {SvgPath(o.record), svg}}) {
      if (const host::Outcome w = host::WriteFileWhole(file, text); !w.ok())
        return Fail(cmd, w.status, w.message);
    }
  }
  if (JsonOutput()) {
    PrintJson({{"scene", spec.value.name},
               {"samples", fed},
               {"of", samples.value.size()},
               {"record", o.record.empty() ? nullptr : nlohmann::ordered_json(o.record)}});
  } else {
    std::fprintf(TextOut(), "%s: %zu of %zu samples rendered%s%s\n", spec.value.name.c_str(), fed,
                 samples.value.size(), o.record.empty() ? "" : "; recorded in ",
                 o.record.empty() ? "" : (o.record + " and " + SvgPath(o.record)).c_str());
  }
  return fed == samples.value.size() ? kExitOk : kExitFailed;
}

}  // namespace

const Command kRenderCommand{
    "render", "render SCENE --input TRAJECTORY.csv [--record OUT.csv]",
    "Plays a scene (docs/scenes.md) to the board from a recorded trajectory (CSV: time_s, x_mm,\n"
    "y_mm, force_n), sample by sample at the trajectory's own pace on the board's clock (a\n"
    "simulator at --speed X is fed X times faster): each sample's targets go to\n"
    "every finger in one frame. A terminal shows each sample's targets as it goes. --record OUT:\n"
    "a CSV of the input, the board's time and each finger's map value and target, and OUT.svg,\n"
    "the path over the tissue. The fingers return to safe when it ends (Ctrl-C ends it early).",
    CmdRender};

}  // namespace palpa::cli
