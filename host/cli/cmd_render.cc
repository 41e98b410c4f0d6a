// palpa render: a scene played to the board from a recorded trajectory, a pen tablet or a
// tactile array, optionally rendered ahead of the display's delay; live status on the terminal,
// and a record of what each finger touched and was asked, with an SVG of the path.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "cli.h"
#include "palpa/host/file_write.h"
#include "palpa/host/scene.h"
#include "palpa/host/scene_evdev.h"
#include "palpa/host/scene_svg.h"
#include "render_inputs.h"
#include "render_record.h"
#include "render_summary.h"

namespace palpa::cli {
namespace {

struct RenderOptions {
  std::string scene, input, record;
  bool predict = false;
  double duration_s = 0;  ///< live inputs: 0 runs until interrupted
};

host::Result<RenderOptions> Options(const std::vector<std::string>& args) {
  RenderOptions o;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--input" || args[i] == "--record" || args[i] == "--duration") {
      const auto value = OptionValue(args, i);
      if (!value.ok()) return value.outcome();
      if (args[i] == "--duration") {
        if (!ParseNumber(value.value, o.duration_s) || !(o.duration_s > 0))
          return {protocol::Status::kInvalidArgument,
                  "--duration " + value.value + ": a number of seconds above 0"};
      } else {
        (args[i] == "--input" ? o.input : o.record) = value.value;
      }
      ++i;
    } else if (args[i] == "--predict") {
      o.predict = true;
    } else if (args[i].rfind("--", 0) == 0 || !o.scene.empty()) {
      return {protocol::Status::kInvalidArgument, "unexpected argument " + args[i]};
    } else {
      o.scene = args[i];
    }
  }
  if (o.scene.empty() || o.input.empty())
    return {protocol::Status::kInvalidArgument,
            std::string("a SCENE file and --input ") + kInputSyntax};
  return o;
}

/// Sleeps until `at` seconds of input time have passed since `start` on the board's clock.
void PaceTo(std::chrono::steady_clock::time_point start, double at, double scale) {
  std::this_thread::sleep_until(start + std::chrono::duration<double>(at / scale));
}

}  // namespace

int CmdRender(Context& c, const std::vector<std::string>& args) {
  const std::string cmd = "render";
  const auto options = Options(args);
  if (!options.ok()) return Usage(cmd, options.message);
  const RenderOptions& o = options.value;
  const auto source = ParseInputSource(o.input);
  if (!source.ok()) return Usage(cmd, source.message);
  const InputSource& in = source.value;
  const auto spec = host::LoadScene(o.scene);
  if (!spec.ok()) return Fail(cmd, spec.status, spec.message, kExitUsage);
  const bool tactile = in.kind == InputSource::kTactileUdp || in.kind == InputSource::kTactileFile;
  if (tactile && !spec.value.tactile)
    return Usage(cmd, o.scene +
                          ": a tactile input needs the scene's input.tactile section "
                          "(its elements, a group per finger, the value range)");
  if (tactile && o.predict)
    return Usage(cmd,
                 "--predict follows a moving hand; a tactile array has no position to predict");
  const bool live = in.kind == InputSource::kEvdev || in.kind == InputSource::kTactileUdp;
  if (!live && o.duration_s > 0)
    return Usage(cmd, "--duration is for live inputs (evdev, tactile-udp)");
  std::vector<host::SceneInput> samples;
  std::vector<host::TactileFrame> frames;
  if (in.kind == InputSource::kTrajectory) {
    auto loaded = host::LoadTrajectory(in.path);
    if (!loaded.ok()) return Fail(cmd, loaded.status, loaded.message, kExitUsage);
    samples = std::move(loaded.value);
  } else if (in.kind == InputSource::kTactileFile) {
    auto loaded = host::LoadTactileStream(in.path, spec.value.tactile->elements);
    if (!loaded.ok()) return Fail(cmd, loaded.status, loaded.message, kExitUsage);
    frames = std::move(loaded.value);
  }
  host::Device* device = c.Device();
  if (device == nullptr) return kExitConnect;
  auto scene = host::Scene::Open(spec.value, *device);
  if (!scene.ok()) return Fail(cmd, scene.status, scene.message, kExitUsage);
  double horizon_s = 0;
  if (o.predict) {
    const auto delay = scene.value->DisplayDelay();
    if (!delay.ok()) return Fail(cmd, delay.status, "--predict: " + delay.message);
    horizon_s = delay.value;
    host::PredictorOptions p;
    p.horizon_s = horizon_s;
    if (const auto ok = scene.value->Predict(p); !ok.ok()) return Fail(cmd, ok.status, ok.message);
  }
  const host::TissueMap& tissue = scene.value->renderer().tissue();
  std::unique_ptr<host::PenTablet> tablet;
  std::unique_ptr<host::TactileUdp> udp;
  if (in.kind == InputSource::kEvdev) {
    const host::TabletSpec t = spec.value.tablet.value_or(host::TabletSpec{});
    auto opened = host::PenTablet::Open(in.path, tissue.extent_x_mm(), tissue.extent_y_mm(),
                                        t.pressure_force, t.touch_force_n);
    if (!opened.ok()) return Fail(cmd, opened.status, opened.message, kExitConnect);
    tablet = std::move(opened.value);
    std::fprintf(stderr, "palpa render: %s, mapped onto %s (%.0f × %.0f mm)\n",
                 host::DescribePad(tablet->mapping().pad).c_str(), tissue.name.c_str(),
                 tissue.extent_x_mm(), tissue.extent_y_mm());
  } else if (in.kind == InputSource::kTactileUdp) {
    auto opened = host::TactileUdp::Open(in.host, in.port, spec.value.tactile->elements);
    if (!opened.ok()) return Fail(cmd, opened.status, opened.message, kExitConnect);
    udp = std::move(opened.value);
    if (in.host.rfind("127.", 0) != 0)
      std::fprintf(stderr,
                   "palpa render: warning: tactile-udp:%s:%u is reachable from other hosts, and "
                   "whoever reaches it drives the fingers (within their limits)\n",
                   in.host.c_str(), static_cast<unsigned>(in.port));
  }

  RenderRecord rec;
  rec.live = !JsonOutput() && isatty(fileno(stdout));
  rec.hand = !tactile;
  rec.predicted = o.predict;
  rec.Header(spec.value);
  const int subscription = device->Subscribe([&](const host::TelemetryFrame& f) {
    const auto& t = f.telemetry;
    rec.board_us = t.first_sample_us + uint64_t{t.tick_count - 1u} * t.sample_interval_us;
  });
  const PollsInterruption polls;
  // Recorded inputs play at their own pace on the board's clock: a simulator running X times
  // faster than real time (palpa-sim --speed X) takes the samples X times sooner.
  const double scale = device->info().time_scale > 0 ? device->info().time_scale : 1.0;
  const auto start = std::chrono::steady_clock::now();
  const auto over = [&] {
    return Interrupted() || (o.duration_s > 0 && std::chrono::steady_clock::now() - start >
                                                     std::chrono::duration<double>(o.duration_s));
  };
  host::Outcome failed;
  size_t total = 0, taken = 0;  // tactile: frames in the input, frames rendered
  const auto feed = [&](const host::SceneInput& s) {
    const auto renders = scene.value->Feed(s);
    if (!renders.ok()) return failed = renders, false;
    const auto* p = scene.value->predictor();
    rec.Row(s, p != nullptr ? &p->last_output() : nullptr, renders.value);
    return true;
  };
  const host::TactileSpec* ts = tactile ? &*spec.value.tactile : nullptr;
  std::optional<host::TactileHold> hold;
  if (ts != nullptr) hold.emplace(ts->hold_s);
  bool soft = true;
  // A tactile array's state at `now`: rendered when a frame was taken or the hold ran out.
  const auto feed_tactile = [&](double now, bool fresh) {
    const std::vector<double>* values = hold->At(now);
    if (!fresh && (values == nullptr) == soft) return true;
    soft = values == nullptr;
    std::vector<double> means;
    if (values != nullptr) means = host::GroupMeans(*ts, *values);
    const auto renders =
        scene.value->FeedValues(values != nullptr ? &means : nullptr, ts->value_lo, ts->value_hi);
    if (!renders.ok()) return failed = renders, false;
    rec.Row({now, 0, 0, 0}, nullptr, renders.value);
    return true;
  };
  switch (in.kind) {
    case InputSource::kTrajectory:
      total = samples.size();
      for (const host::SceneInput& s : samples) {
        if (over()) break;
        PaceTo(start, s.time_s - samples.front().time_s, scale);
        if (!feed(s)) break;
      }
      break;
    case InputSource::kEvdev:
      while (!over()) {
        const auto s = tablet->Next(50);
        if (!s.ok()) {
          failed = s;
          break;
        }
        if (s.value && !feed(*s.value)) break;
      }
      total = rec.fed;
      break;
    case InputSource::kTactileFile: {
      total = frames.size();
      // Stepped every 5 ms of stream time, so a stall longer than the hold goes soft on time.
      const double t0 = frames.front().time_s;
      size_t next = 0;
      for (double now = t0; next < frames.size() || !soft; now += 0.005) {
        if (over()) break;
        PaceTo(start, now - t0, scale);
        bool fresh = false;
        while (next < frames.size() && frames[next].time_s <= now + 1e-9)
          fresh |= hold->Receive(frames[next], frames[next].time_s) && ++taken, ++next;
        if (!feed_tactile(now, fresh)) break;
        if (next == frames.size() && now > frames.back().time_s + ts->hold_s) break;
      }
      break;
    }
    case InputSource::kTactileUdp:
      while (!over()) {
        const auto frame = udp->Receive(5);
        if (!frame.ok()) {
          failed = frame;
          break;
        }
        const bool fresh = frame.value && hold->Receive(*frame.value, frame.value->time_s);
        taken += fresh ? 1 : 0;
        if (!feed_tactile(host::MonotonicSeconds(), fresh)) break;
      }
      total = rec.fed;
      break;
  }
  device->Unsubscribe(subscription);
  if (rec.live) std::printf("\n");
  if (!failed.ok()) return Fail(cmd, failed.status, failed.message);
  if (!o.record.empty()) {
    const host::SceneRenderer& r = scene.value->renderer();
    const auto end = rec.path.empty() ? std::pair{0.0, 0.0} : rec.path.back();
    const std::string svg = host::SceneSvg(r.tissue(), r.layout(), end.first, end.second, rec.path,
                                           spec.value.name + " — " + o.input);
    // A tactile array has no path over the tissue: its record is the CSV alone.
    std::vector<std::pair<std::string, std::string>> files{{o.record, rec.csv}};
    if (rec.hand) files.emplace_back(SvgPath(o.record), svg);
    for (const auto& [file, text] : files) {
      if (const host::Outcome w = host::WriteFileWhole(file, text); !w.ok())
        return Fail(cmd, w.status, w.message);
    }
  }
  RenderSummary summary{spec.value.name, o.input, o.record, tactile,  rec.hand,
                        rec.fed,         total,   taken,    horizon_s};
  summary.predictor = scene.value->predictor();
  summary.hold = hold ? &*hold : nullptr;
  summary.udp = udp.get();
  summary.tablet = tablet.get();
  PrintRenderSummary(summary);
  if (live) return kExitOk;
  return (tactile ? taken : rec.fed) == total ? kExitOk : kExitFailed;
}

const Command kRenderCommand{
    "render", "render SCENE --input SOURCE [--predict] [--duration S] [--record OUT.csv]",
    "Plays a scene (docs/scenes.md) to the board, every finger's target in one frame per sample.\n"
    "SOURCE is a recorded trajectory (TRAJECTORY.csv or file:PATH; time_s, x_mm, y_mm, force_n),\n"
    "played at its own pace on the board's clock (a simulator at --speed X is fed X times "
    "faster);\n"
    "evdev:/dev/input/eventN, a pen tablet or touchpad mapped onto the tissue (pressure through\n"
    "the scene's input.tablet form); tactile-udp:[HOST:]PORT, a tactile array's frames over UDP\n"
    "(on loopback unless HOST names another address; 0.0.0.0: every one);\n"
    "or tactile-file:STREAM.csv, a recorded array stream (both grouped per finger by the scene's\n"
    "input.tactile; a stalled stream holds for hold_s, then the fingers go soft). Live inputs run\n"
    "until Ctrl-C or --duration. --predict renders where the hand will be after the fingers'\n"
    "calibrated delay (their lines' chamber models). --record OUT: a CSV of the input, the\n"
    "board's time and each finger's map value and target, and OUT.svg, the path over the tissue.\n"
    "The fingers return to safe when it ends.",
    CmdRender};

}  // namespace palpa::cli
