// palpa scene: generate a phantom's tissue file, draw a scene as SVG.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <sstream>

#include "cli.h"
#include "palpa/host/file_write.h"
#include "palpa/host/scene_file.h"
#include "palpa/host/scene_svg.h"

namespace palpa::cli {

int CalibrateInput(Context& c, const std::vector<std::string>& args);  // cmd_scene_input.cc

namespace {

using protocol::Status;

/// "a,b,c" as `count` numbers, or a usage message naming the option.
host::Result<std::vector<double>> Numbers(const std::string& option, const std::string& text,
                                          size_t count) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    double v = 0;
    if (!ParseNumber(part, v)) break;
    out.push_back(v);
  }
  if (out.size() != count ||
      std::count(text.begin(), text.end(), ',') != static_cast<long>(count - 1)) {
    return {Status::kInvalidArgument, option + " " + text + ": expected " + std::to_string(count) +
                                          " numbers, comma-separated"};
  }
  return out;
}

/// The library names inclusions from 0 ("inclusions[1].depth_mm: ... inclusions[0]"); the command
/// line from 1, by the --inclusion that gave each ("--inclusion 2: depth_mm: ... --inclusion 1").
std::string AsArguments(const std::string& message) {
  const std::string key = "inclusions[";
  std::string out;
  size_t from = 0;
  for (size_t at = message.find(key); at != std::string::npos; at = message.find(key, from)) {
    const size_t close = message.find(']', at);
    double n = 0;
    if (close == std::string::npos ||
        !ParseNumber(message.substr(at + key.size(), close - at - key.size()), n))
      break;
    out +=
        message.substr(from, at - from) + "--inclusion " + std::to_string(static_cast<int>(n) + 1);
    from = close + 1;
    if (from < message.size() && message[from] == '.') {  // a field of it
      out += ": ";
      ++from;
    }
  }
  return out + message.substr(from);
}

int Phantom(Context&, std::vector<std::string> args) {
  const std::string cmd = "scene phantom";
  host::PhantomSpec spec;
  bool preset = false, custom = false;
  std::string out;
  for (size_t i = 0; i < args.size(); i += 2) {
    const auto value = OptionValue(args, i);
    if (!value.ok()) return Usage(cmd, value.message);
    const std::string& a = args[i];
    const std::string& v = value.value;
    if (a == "--preset") {
      if (v != host::ThreeCubePhantom().name)
        return Usage(cmd, "--preset " + v + ": the presets are thesis-three-cube");
      spec = host::ThreeCubePhantom();
      preset = true;
    } else if (a == "--out") {
      out = v;
    } else if (a == "--size" || a == "--inclusion") {
      const auto n = Numbers(a, v, a == "--size" ? 3 : 6);
      if (!n.ok()) return Usage(cmd, n.message);
      custom = true;
      const auto& x = n.value;
      if (a == "--size") {
        spec.size_x_mm = x[0], spec.size_y_mm = x[1], spec.height_mm = x[2];
      } else {
        spec.inclusions.push_back({"inclusion " + std::to_string(spec.inclusions.size() + 1), x[0],
                                   x[1], x[2], x[2], x[3], x[4], x[5]});
      }
    } else if (a == "--background" || a == "--pitch") {
      double n = 0;
      if (!ParseNumber(v, n)) return Usage(cmd, a + " " + v + ": expected a number");
      (a == "--background" ? spec.background : spec.pitch_mm) = n;
      custom = custom || a == "--background";
    } else if (a == "--unit" || a == "--name") {
      (a == "--unit" ? spec.unit : spec.name) = v;
    } else {
      return Usage(cmd, "unknown option " + a);
    }
  }
  if (preset == custom)
    return Usage(cmd, "either --preset NAME or --size X,Y,H --background E [--inclusion ...]");
  if (out.empty()) return Usage(cmd, "--out FILE: where the tissue file goes");
  if (spec.name.empty()) spec.name = "block";
  const auto map = host::GeneratePhantom(spec);
  if (!map.ok()) return Fail(cmd, map.status, AsArguments(map.message), kExitUsage);
  const auto text = host::SerializeTissue(map.value);
  if (!text.ok()) return Fail(cmd, text.status, text.message);
  if (const host::Outcome w = host::WriteFileWhole(out, text.value); !w.ok())
    return Fail(cmd, w.status, w.message);
  const auto [lo, hi] = map.value.Range();
  if (JsonOutput()) {
    PrintJson({{"tissue", out},
               {"name", map.value.name},
               {"points", {map.value.nx, map.value.ny}},
               {"range", {lo, hi}},
               {"unit", map.value.unit}});
  } else {
    std::printf("%s: %s, %zu × %zu points over %g × %g mm, %g … %g %s\n", out.c_str(),
                map.value.name.c_str(), map.value.nx, map.value.ny, map.value.extent_x_mm(),
                map.value.extent_y_mm(), lo, hi, map.value.unit.c_str());
  }
  return kExitOk;
}

int Show(Context&, std::vector<std::string> args) {
  const std::string cmd = "scene show";
  std::string scene_path, out;
  std::optional<std::vector<double>> at;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out" || args[i] == "--at") {
      const auto value = OptionValue(args, i);
      if (!value.ok()) return Usage(cmd, value.message);
      if (args[i] == "--out") {
        out = value.value;
      } else {
        const auto n = Numbers("--at", value.value, 2);
        if (!n.ok()) return Usage(cmd, n.message);
        at = n.value;
      }
      ++i;
    } else if (args[i].rfind("--", 0) == 0 || !scene_path.empty()) {
      return Usage(cmd, "unexpected argument " + args[i]);
    } else {
      scene_path = args[i];
    }
  }
  if (scene_path.empty() || out.empty()) return Usage(cmd, "a SCENE file and --out FILE.svg");
  const auto spec = host::LoadScene(scene_path);
  if (!spec.ok()) return Fail(cmd, spec.status, spec.message, kExitUsage);
  const auto tissue = host::LoadSceneTissue(spec.value);
  if (!tissue.ok()) return Fail(cmd, tissue.status, tissue.message, kExitUsage);
  const host::FingerLayout layout = host::MakeLayout(spec.value.layout);
  const double x = at ? (*at)[0] : tissue.value.extent_x_mm() / 2;
  const double y = at ? (*at)[1] : tissue.value.extent_y_mm() / 2;
  const std::string svg =
      host::SceneSvg(tissue.value, layout, x, y, {}, spec.value.name + " — " + layout.name);
  if (const host::Outcome w = host::WriteFileWhole(out, svg); !w.ok())
    return Fail(cmd, w.status, w.message);
  if (JsonOutput()) {
    PrintJson({{"svg", out}, {"scene", spec.value.name}, {"at", {x, y}}});
  } else {
    std::printf("%s: %s, the fingers about (%g, %g) mm\n", out.c_str(), spec.value.name.c_str(), x,
                y);
  }
  return kExitOk;
}

int CmdScene(Context& c, const std::vector<std::string>& args) {
  if (args.empty()) return Usage("scene", "phantom, show or calibrate-input");
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args[0] == "phantom") return Phantom(c, rest);
  if (args[0] == "show") return Show(c, rest);
  if (args[0] == "calibrate-input") return CalibrateInput(c, rest);
  const std::string near = Suggest(args[0], {"phantom", "show", "calibrate-input"});
  return Usage("scene", "unknown subcommand " + args[0] +
                            (near.empty() ? "" : " (did you mean " + near + "?)"));
}

}  // namespace

const Command kSceneCommand{
    "scene",
    "scene phantom (--preset NAME | --size X,Y,H --background E [--inclusion "
    "X,Y,SIDE,THICK,DEPTH,E]"
    "...) [--unit U] [--pitch MM] [--name N] --out FILE | show SCENE [--at X,Y] --out FILE.svg | "
    "calibrate-input SCENE (--a A --b B | --presses PRESSES.csv | --pen evdev:PATH --rig RIG.json "
    "[--count N]) [--out FILE]",
    "Scenes: a virtual tissue rendered to the fingers (docs/scenes.md). No board is needed.\n"
    "phantom: writes the tissue file of a generated phantom — the preset thesis-three-cube, or\n"
    "a block of X × Y × H mm at stiffness E (in --unit, kPa by default) with square inclusions\n"
    "centred at X,Y of SIDE mm, THICK mm thick, their top DEPTH mm below the surface, stiffness\n"
    "E; the map's --pitch is 0.5 mm by default.\n"
    "show: draws a scene file as SVG — its tissue in colour, the fingers' contact discs about\n"
    "--at X,Y (the tissue's centre by default).\n"
    "calibrate-input: sets the scene's pen pressure form f = a·e^(b·level) (input.tablet;\n"
    "levels 0 … 1023 whatever the pad's range): from --a and --b, fitted to recorded presses\n"
    "(CSV: level,force_n), or fitted to --count presses (5) made now with the pen on the rig's\n"
    "force sensor, each held still until level and force are steady. Written to the scene file,\n"
    "or --out, the rest of the file as it was.",
    CmdScene};

}  // namespace palpa::cli
