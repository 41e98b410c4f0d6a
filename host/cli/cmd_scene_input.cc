// palpa scene calibrate-input: a scene's pen pressure form f = a·e^(b·level) set from a and b as
// given, fitted from recorded presses, or fitted from presses made now on a rig's force sensor;
// written into the scene file's input.tablet, everything else in the file kept as it was.
#include <chrono>
#include <cstdio>
#include <thread>

#include "cli.h"
#include "palpa/calibration/input_presses.h"
#include "palpa/calibration/rig_file.h"
#include "palpa/host/file_read.h"
#include "palpa/host/file_write.h"
#include "palpa/host/json_check.h"
#include "palpa/host/scene_evdev.h"
#include "palpa/host/scene_file.h"
#include "render_inputs.h"

namespace palpa::cli {
namespace {

namespace cal = palpa::calibration;
using protocol::Status;

/// Real time for a person pressing a pen.
struct SteadyTime final : cal::RigTime {
  double Now() override {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  void Wait(double s) override { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }
};

/// The pen tablet as the press procedure reads it.
struct TabletLevels final : cal::PenLevels {
  host::PenTablet& tablet;
  explicit TabletLevels(host::PenTablet& t) : tablet(t) {}
  host::Result<std::optional<cal::PenState>> Next(int timeout_ms) override {
    const auto s = tablet.Next(timeout_ms);
    if (!s.ok()) return s.outcome();
    if (!s.value) return std::optional<cal::PenState>();
    return std::optional<cal::PenState>(cal::PenState{tablet.last_touching(), tablet.last_level()});
  }
};

struct Args {
  std::string scene, out, presses, pen, rig;
  std::optional<double> a, b;
  size_t count = 5;
};

host::Result<Args> Parse(const std::vector<std::string>& args) {
  Args o;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& k = args[i];
    if (k == "--out" || k == "--presses" || k == "--pen" || k == "--rig" || k == "--a" ||
        k == "--b" || k == "--count") {
      const auto v = OptionValue(args, i++);
      if (!v.ok()) return v.outcome();
      double n = 0;
      if ((k == "--a" || k == "--b" || k == "--count") && !ParseNumber(v.value, n))
        return {Status::kInvalidArgument, k + " " + v.value + ": expected a number"};
      if (k == "--out") o.out = v.value;
      if (k == "--presses") o.presses = v.value;
      if (k == "--pen") o.pen = v.value;
      if (k == "--rig") o.rig = v.value;
      if (k == "--a") o.a = n;
      if (k == "--b") o.b = n;
      if (k == "--count") {
        if (!(n >= 2 && n <= 50 && n == std::floor(n)))
          return {Status::kInvalidArgument, "--count " + v.value + ": 2 … 50 presses"};
        o.count = static_cast<size_t>(n);
      }
    } else if (k.rfind("--", 0) == 0 || !o.scene.empty()) {
      return {Status::kInvalidArgument, "unexpected argument " + k};
    } else {
      o.scene = k;
    }
  }
  const int ways = (o.a || o.b) + !o.presses.empty() + (!o.pen.empty() || !o.rig.empty());
  if (o.scene.empty() || ways != 1)
    return {Status::kInvalidArgument,
            "a SCENE file and one of --a A --b B, --presses PRESSES.csv, or --pen "
            "evdev:/dev/input/eventN --rig RIG.json"};
  if ((o.a || o.b) && !(o.a && o.b)) return {Status::kInvalidArgument, "--a and --b go together"};
  if ((!o.pen.empty() || !o.rig.empty()) && (o.pen.empty() || o.rig.empty()))
    return {Status::kInvalidArgument, "--pen and --rig go together"};
  return o;
}

}  // namespace

int CalibrateInput(Context&, const std::vector<std::string>& args) {
  const std::string cmd = "scene calibrate-input";
  const auto parsed = Parse(args);
  if (!parsed.ok()) return Usage(cmd, parsed.message);
  const Args& o = parsed.value;
  // The scene as written (its JSON kept, so relative paths and the rest stay as they are).
  const auto text = host::ReadFileWhole(o.scene, host::kSceneFileLimits);
  if (!text.ok()) return Fail(cmd, text.status, text.message, kExitUsage);
  const auto spec = host::LoadScene(o.scene);
  if (!spec.ok()) return Fail(cmd, spec.status, spec.message, kExitUsage);
  host::PressureFit fit;
  if (o.a) {
    fit.model = {*o.a, *o.b};
    if (const auto ok = host::CheckPressureForce(fit.model); !ok.ok())
      return Usage(cmd, "--a, --b: " + ok.message);
  } else {
    std::vector<host::Press> presses;
    if (!o.presses.empty()) {
      auto loaded = host::LoadPresses(o.presses);
      if (!loaded.ok()) return Fail(cmd, loaded.status, loaded.message, kExitUsage);
      presses = std::move(loaded.value);
    } else {
      const auto source = ParseInputSource(o.pen);
      if (!source.ok() || source.value.kind != InputSource::kEvdev)
        return Usage(cmd, "--pen " + o.pen + ": expected evdev:/dev/input/eventN");
      auto tablet = host::PenTablet::Open(source.value.path, 1, 1, {}, 1.0);
      if (!tablet.ok()) return Fail(cmd, tablet.status, tablet.message, kExitConnect);
      if (!tablet.value->mapping().pad.pressure)
        return Fail(cmd, Status::kInvalidArgument,
                    host::DescribePad(tablet.value->mapping().pad) +
                        ": nothing to calibrate without a pressure axis (touch_force_n applies)",
                    kExitUsage);
      const auto rig = cal::LoadRigDescription(o.rig);
      if (!rig.ok()) return Fail(cmd, rig.status, rig.message, kExitUsage);
      auto devices = cal::OpenRigDevices(rig.value);
      if (!devices.ok()) return Fail(cmd, devices.status, devices.message, kExitConnect);
      TabletLevels pen(*tablet.value);
      SteadyTime time;
      cal::PressOptions options;
      options.presses = o.count;
      auto taken = cal::CollectPresses(
          pen, *devices.value.force, time, options,
          [](const std::string& s) { std::fprintf(stderr, "palpa: %s\n", s.c_str()); });
      if (!taken.ok()) return Fail(cmd, taken.status, taken.message);
      presses = std::move(taken.value);
    }
    const auto fitted = host::FitPressureForce(presses);
    if (!fitted.ok())
      return Fail(cmd, fitted.status, (o.presses.empty() ? "" : o.presses + ": ") + fitted.message,
                  kExitUsage);
    fit = fitted.value;
  }
  // input.tablet.pressure_force replaced; the document checked whole before it is written.
  auto doc = host::ParseJson(text.value);
  if (!doc.ok()) return Fail(cmd, doc.status, doc.message, kExitUsage);
  nlohmann::json& tablet = doc.value["input"]["tablet"];
  tablet["pressure_force"] = {{"a_n", fit.model.a_n}, {"b_per_level", fit.model.b_per_level}};
  const std::string written = doc.value.dump(2) + "\n";
  const std::string out = o.out.empty() ? o.scene : o.out;
  const size_t slash = o.scene.rfind('/');
  if (const auto back =
          host::ParseScene(written, slash == std::string::npos ? "" : o.scene.substr(0, slash));
      !back.ok())
    return Fail(cmd, back.status, "the scene would not read back: " + back.message);
  if (const auto w = host::WriteFileWhole(out, written); !w.ok())
    return Fail(cmd, w.status, w.message);
  if (JsonOutput()) {
    nlohmann::ordered_json j = {
        {"scene", out}, {"a_n", fit.model.a_n}, {"b_per_level", fit.model.b_per_level}};
    if (fit.presses > 0)
      j["fit"] = {{"presses", fit.presses}, {"rms_n", fit.rms_n}, {"max_error_n", fit.max_error_n}};
    PrintJson(j);
  } else {
    std::printf(
        "%s: pen pressure f = %.5g · e^(%.5g · level) N (%.3g N at level 0, %.3g N at 1023)",
        out.c_str(), fit.model.a_n, fit.model.b_per_level, host::ForceAtLevel(fit.model, 0),
        host::ForceAtLevel(fit.model, 1023));
    if (fit.presses > 0)
      std::printf("; fitted to %zu presses, RMS %.3g N, worst %.3g N", fit.presses, fit.rms_n,
                  fit.max_error_n);
    std::printf("\n");
  }
  return kExitOk;
}

}  // namespace palpa::cli
