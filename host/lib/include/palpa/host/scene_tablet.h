// Pen tablets and touchpads as scene inputs: the pad's axes mapped linearly onto the tissue (the
// thesis mapped its pad's 125 × 85 mm onto the surface), and the pen's pressure level turned into
// force by the thesis's exponential f = a·e^(b·level), taken as given or fitted from presses.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/outcome.h"
#include "palpa/host/scene_input.h"

namespace palpa::host {

/// Pressure is read as a level 0 … kPressureLevels − 1 whatever the pad reports (its own range
/// scaled onto these), so one calibration form serves every pad: the thesis's 1 024 levels.
inline constexpr int kPressureLevels = 1024;

/// f = a·e^(b·level) in N. The thesis's fit for its pad: a = 0.0827 N, b = 0.0039 per level
/// (0.083 N at the lightest touch, 4.5 N at full pressure).
struct PressureForce {
  double a_n = 0.0827;
  double b_per_level = 0.0039;
};

double ForceAtLevel(const PressureForce& p, double level);
/// a within 1e-6 … 100 N, b within −0.1 … 0.1 per level, and at most kMaxInputForceN at the top
/// level; the reason names the value ("pressure_force: a = 0 N is outside …").
Outcome CheckPressureForce(const PressureForce& p);

/// One press on a force sensor: the pen's level and the force the sensor read at that moment.
struct Press {
  double level = 0;
  double force_n = 0;
};

struct PressureFit {
  PressureForce model;
  double rms_n = 0;  ///< of the forces, against the fit
  double max_error_n = 0;
  size_t presses = 0;
};

/// The least-squares line through ln f against level (the exponential's own linear form): at
/// least two presses at different levels, levels 0 … 1 023, forces above 0 and at most
/// kMaxInputForceN; the reason names the press ("presses[2]: force 0 N: ...").
Result<PressureFit> FitPressureForce(const std::vector<Press>& presses);

/// Presses as CSV: the header `level,force_n`, then one press a line ('#' comments allowed).
inline constexpr const char* kPressesHeader = "level,force_n";
Result<std::vector<Press>> ParsePresses(const std::string& text, const std::string& source);
Result<std::vector<Press>> LoadPresses(const std::string& path);

/// One absolute axis of a pad, as the device reports it.
struct PadAxis {
  int minimum = 0, maximum = 0;
  int resolution = 0;  ///< units per mm (0: the device does not say)
  /// The axis's length in mm, when the device states its resolution.
  std::optional<double> Length() const;
};

/// What a pad offers: its name, x and y, and pressure if it has an axis for it.
struct PadGeometry {
  std::string name;
  PadAxis x, y;
  std::optional<PadAxis> pressure;
  bool has_touch = false;  ///< BTN_TOUCH: contact reported apart from pressure
};

/// A pad mapped onto a tissue: its whole x range onto 0 … extent_x, its y range onto extent_y …
/// 0 (a pad's y grows downwards, a tissue's upwards, as an image's rows: the pad's top edge is the
/// tissue's far edge).
struct TabletMapping {
  PadGeometry pad;
  double extent_x_mm = 0, extent_y_mm = 0;
  PressureForce pressure_force;
  /// A pad without a pressure axis (most touchpads) presses with this while touching.
  double touch_force_n = 1.0;
};

/// Whether a pad can drive a scene: an x and a y axis that rise, a pressure axis (if any) that
/// rises, a tissue extent above 0, a valid pressure form. The reason names the pad and what is
/// missing or wrong.
Outcome CheckTabletMapping(const TabletMapping& m);

/// The pad's state (raw axis values; `touching` is BTN_TOUCH, or pressure above its minimum on a
/// pad without it) as a scene input at time `time_s`. Not touching presses with 0 N.
SceneInput MapPad(const TabletMapping& m, double time_s, int x, int y, std::optional<int> pressure,
                  bool touching);
/// A raw pressure value as a level 0 … 1 023.
double PressureLevel(const PadAxis& pressure, int value);

/// "Wacom Intuos S Pen: 152 × 95 mm, 4 096 pressure levels" — what the pad is, in words.
std::string DescribePad(const PadGeometry& pad);

}  // namespace palpa::host
