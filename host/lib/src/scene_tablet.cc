// Pen tablets and touchpads: pad axes onto the tissue, pressure levels to force, and the fit of
// the pressure form from presses on a force sensor.
#include "palpa/host/scene_tablet.h"

#include <algorithm>
#include <cmath>

#include "number_text.h"
#include "palpa/host/scene_files.h"

namespace palpa::host {

double ForceAtLevel(const PressureForce& p, double level) {
  return p.a_n * std::exp(p.b_per_level * level);
}

Outcome CheckPressureForce(const PressureForce& p) {
  if (!(p.a_n >= 1e-6 && p.a_n <= 100))
    return Outcome::Fail(Status::kInvalidArgument,
                         "pressure_force: a = " + Num(p.a_n) + " N is outside 1e-06 … 100 N");
  if (!(p.b_per_level >= -0.1 && p.b_per_level <= 0.1))
    return Outcome::Fail(Status::kInvalidArgument, "pressure_force: b = " + Num(p.b_per_level) +
                                                       " per level is outside -0.1 … 0.1");
  const double top = ForceAtLevel(p, kPressureLevels - 1);
  if (!(top <= kMaxInputForceN)) {
    return Outcome::Fail(Status::kInvalidArgument, "pressure_force: a·e^(b·1023) = " + Num(top) +
                                                       " N at full pressure, more than " +
                                                       Num(kMaxInputForceN) + " N");
  }
  return {};
}

Result<PressureFit> FitPressureForce(const std::vector<Press>& presses) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t k = 0; k < presses.size(); ++k) {
    const Press& p = presses[k];
    const std::string where = "presses[" + std::to_string(k) + "]";
    if (!(p.level >= 0 && p.level <= kPressureLevels - 1))
      return {Status::kInvalidArgument, where + ": level " + Num(p.level) + " is outside 0 … 1023"};
    if (!(p.force_n > 0 && p.force_n <= kMaxInputForceN)) {
      return {Status::kInvalidArgument, where + ": force " + Num(p.force_n) +
                                            " N: must be above 0 and at most " +
                                            Num(kMaxInputForceN) + " N (ln f is fitted)"};
    }
    const double y = std::log(p.force_n);
    n += 1, sx += p.level, sy += y, sxx += p.level * p.level, sxy += p.level * y;
  }
  const double spread = n * sxx - sx * sx;
  if (presses.size() < 2 || !(spread > 1e-9 * std::max(1.0, n * sxx))) {
    return {Status::kInvalidArgument, "presses: " + std::to_string(presses.size()) +
                                          " presses; the fit needs at least two at different "
                                          "levels"};
  }
  PressureFit fit;
  fit.model.b_per_level = (n * sxy - sx * sy) / spread;
  fit.model.a_n = std::exp((sy - fit.model.b_per_level * sx) / n);
  double sum = 0;
  for (const Press& p : presses) {
    const double e = ForceAtLevel(fit.model, p.level) - p.force_n;
    sum += e * e;
    fit.max_error_n = std::max(fit.max_error_n, std::fabs(e));
  }
  fit.rms_n = std::sqrt(sum / n);
  fit.presses = presses.size();
  if (const Outcome ok = CheckPressureForce(fit.model); !ok.ok()) {
    return {Status::kInvalidArgument, "the presses fit " + ok.message};
  }
  return fit;
}

Result<std::vector<Press>> ParsePresses(const std::string& text, const std::string& source) {
  const auto lines = CsvDataLines(text);
  std::string header;
  if (!lines.empty()) {
    for (char c : lines[0].second)
      if (c != ' ' && c != '\t') header += c;
  }
  if (header != kPressesHeader) {
    return {Status::kInvalidArgument, source + ": line " +
                                          (lines.empty() ? "1" : std::to_string(lines[0].first)) +
                                          ": expected the header " + kPressesHeader};
  }
  std::vector<Press> presses;
  for (size_t k = 1; k < lines.size() && k <= 10000; ++k) {
    const std::string where = source + ": line " + std::to_string(lines[k].first);
    const auto v = ParseCsvNumbers(lines[k].second, where, 2);
    if (!v.ok()) return v.outcome();
    if (v.value.size() != 2)
      return {Status::kInvalidArgument, where + ": expected 2 values (" + kPressesHeader + ")"};
    presses.push_back({v.value[0], v.value[1]});
  }
  if (lines.size() > 10001) return {Status::kInvalidArgument, source + ": more than 10000 presses"};
  return presses;
}

Result<std::vector<Press>> LoadPresses(const std::string& path) {
  const Result<std::string> text = ReadFileWhole(path, {"presses", 1024 * 1024});
  if (!text.ok()) return text.outcome();
  return ParsePresses(text.value, path);
}

std::optional<double> PadAxis::Length() const {
  if (resolution <= 0) return std::nullopt;
  return static_cast<double>(maximum - minimum) / resolution;
}

Outcome CheckTabletMapping(const TabletMapping& m) {
  const std::string pad = "input device \"" + m.pad.name + "\"";
  if (!(m.pad.x.maximum > m.pad.x.minimum))
    return Outcome::Fail(Status::kInvalidArgument,
                         pad + ": its absolute x axis (ABS_X) has no range (" +
                             std::to_string(m.pad.x.minimum) + " … " +
                             std::to_string(m.pad.x.maximum) + ")");
  if (!(m.pad.y.maximum > m.pad.y.minimum))
    return Outcome::Fail(Status::kInvalidArgument,
                         pad + ": its absolute y axis (ABS_Y) has no range (" +
                             std::to_string(m.pad.y.minimum) + " … " +
                             std::to_string(m.pad.y.maximum) + ")");
  if (m.pad.pressure && !(m.pad.pressure->maximum > m.pad.pressure->minimum))
    return Outcome::Fail(Status::kInvalidArgument,
                         pad + ": its pressure axis (ABS_PRESSURE) has no range (" +
                             std::to_string(m.pad.pressure->minimum) + " … " +
                             std::to_string(m.pad.pressure->maximum) + ")");
  if (!(m.extent_x_mm > 0 && m.extent_y_mm > 0 && std::isfinite(m.extent_x_mm) &&
        std::isfinite(m.extent_y_mm)))
    return Outcome::Fail(Status::kInvalidArgument, "the tissue has no extent to map the pad onto");
  if (!(m.touch_force_n >= 0 && m.touch_force_n <= kMaxInputForceN))
    return Outcome::Fail(Status::kInvalidArgument, "touch_force_n: " + Num(m.touch_force_n) +
                                                       " N is outside 0 … " + Num(kMaxInputForceN) +
                                                       " N");
  return CheckPressureForce(m.pressure_force);
}

double PressureLevel(const PadAxis& p, int value) {
  const double span = static_cast<double>(p.maximum) - p.minimum;
  const double share = span > 0 ? (static_cast<double>(value) - p.minimum) / span : 0.0;
  return std::clamp(share, 0.0, 1.0) * (kPressureLevels - 1);
}

SceneInput MapPad(const TabletMapping& m, double time_s, int x, int y, std::optional<int> pressure,
                  bool touching) {
  const auto share = [](const PadAxis& a, int v) {
    return std::clamp(
        (static_cast<double>(v) - a.minimum) / (static_cast<double>(a.maximum) - a.minimum), 0.0,
        1.0);
  };
  SceneInput in;
  in.time_s = time_s;
  in.x_mm = share(m.pad.x, x) * m.extent_x_mm;
  in.y_mm = (1.0 - share(m.pad.y, y)) * m.extent_y_mm;
  if (touching) {
    in.force_n = m.pad.pressure && pressure
                     ? ForceAtLevel(m.pressure_force, PressureLevel(*m.pad.pressure, *pressure))
                     : m.touch_force_n;
    in.force_n = std::clamp(in.force_n, 0.0, kMaxInputForceN);
  }
  return in;
}

std::string DescribePad(const PadGeometry& pad) {
  std::string s = pad.name + ": ";
  const auto w = pad.x.Length(), h = pad.y.Length();
  char size[64];
  if (w && h) {
    std::snprintf(size, sizeof(size), "%.0f × %.0f mm", *w, *h);
    s += size;
  } else {
    s += "size not stated";
  }
  s += pad.pressure ? ", " + std::to_string(pad.pressure->maximum - pad.pressure->minimum + 1) +
                          " pressure levels"
                    : ", no pressure axis";
  return s;
}

}  // namespace palpa::host
