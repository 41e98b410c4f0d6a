// Measurements at the surface: pneumatic deformation sweeps, jamming presses, a line fit.
#include "palpa/calibration/procedures.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "procedure_support.h"

namespace palpa::calibration {

RigStatus DeformationSweep(Rig& rig, uint8_t finger, const std::vector<double>& kpa, double dwell_s,
                           double zero_mm, const ContactOptions& o, std::vector<SweepSample>* out,
                           double expected_mm) {
  const uint8_t line = rig.board.driven_line(finger);
  double expected = std::isnan(expected_mm) ? zero_mm : expected_mm;
  for (double drive : kpa) {
    RigStatus s = rig.board.SetDrive(finger, drive, 0);
    if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
    rig.time.Wait(dwell_s);
    double surface = 0, measured = 0;
    for (int t = 0; t < std::max(1, o.touches); ++t) {
      double touch = 0;
      s = FindSurface(rig, t == 0 ? expected : surface / t, o, &touch);
      if (!s.ok()) return s;
      surface += touch;
    }
    surface /= std::max(1, o.touches);
    s = rig.board.MeasuredKpa(line, &measured);
    if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
    out->push_back({measured * 1000, (surface - zero_mm) * 1000});
    expected = surface;
  }
  return rig.board.SetDrive(finger, 0, 0);
}

RigStatus Press(Rig& rig, double surface_mm, double depth_mm, double speed_mm_s, PressCycle* out) {
  *out = PressCycle{};
  if (surface_mm - depth_mm < rig.limits.min_position_mm) {
    return AbortSafe(
        rig, Status::kOutOfRange,
        "press to " + Num(surface_mm - depth_mm) + " mm refused: outside the stage's limits");
  }
  RigStatus s = GuardedMove(rig, surface_mm + 0.2, 2.0);
  if (!s.ok()) return s;
  // Clear of the finger the sensor should read its tare: ten readings, a tenth of a second.
  s = ReadForceMean(rig, 10, &out->free_force_n);
  if (!s.ok()) return s;
  auto sweep = [&](double to, std::vector<std::pair<double, double>>* samples) {
    RigStatus r = rig.stage.MoveTo(to, speed_mm_s);
    if (!r.ok()) return AbortSafe(rig, r.status, "stage: " + r.message);
    const double step_s = 0.01 / speed_mm_s;  // a reading per 10 µm of travel
    for (;;) {
      double force = 0, position = 0;
      r = Watch(rig, &force, &position);
      if (!r.ok()) return AbortSafe(rig, r.status, r.message);
      const double depth = surface_mm - position;
      if (depth >= 0) samples->push_back({depth, force});
      out->peak_force_n = std::max(out->peak_force_n, force);
      bool moving = false;
      rig.stage.Moving(&moving);
      if (!moving) return RigStatus{};
      rig.time.Wait(step_s);
    }
  };
  s = sweep(surface_mm - depth_mm, &out->loading);
  if (s.ok()) s = sweep(surface_mm + 0.2, &out->unloading);
  if (!s.ok()) return s;
  // Stiffness: the Hooke's-law slope at contact, from F = k·d + q·d² over the loading branch
  // (the jammed material stiffens slightly with depth; a straight line would fold that in).
  double s11 = 0, s12 = 0, s22 = 0, b1 = 0, b2 = 0, sy = 0, syy = 0;
  for (const auto& [d, f] : out->loading) {
    s11 += d * d;
    s12 += d * d * d;
    s22 += d * d * d * d;
    b1 += d * f;
    b2 += d * d * f;
    sy += f;
    syy += f * f;
  }
  const double det = s11 * s22 - s12 * s12;
  if (out->loading.size() < 3 || det <= 0)
    return AbortSafe(rig, Status::kUnavailable, "press: too few readings to fit");
  const double k = (b1 * s22 - b2 * s12) / det, q = (s11 * b2 - s12 * b1) / det;
  double residual = 0;
  for (const auto& [d, f] : out->loading)
    residual += (f - k * d - q * d * d) * (f - k * d - q * d * d);
  const double n = static_cast<double>(out->loading.size());
  const double spread = syy - sy * sy / n;
  out->stiffness_n_per_mm = k;
  out->residual_n = n > 2 ? std::sqrt(residual / (n - 2)) : 0;
  out->r2 = spread > 0 ? 1 - residual / spread : 1;
  // Loop area: ∫F dd loading minus unloading (trapezoids, N·mm = mJ).
  auto work = [](std::vector<std::pair<double, double>> v) {
    std::sort(v.begin(), v.end());
    double w = 0;
    for (size_t i = 1; i < v.size(); ++i)
      w += 0.5 * (v[i].second + v[i - 1].second) * (v[i].first - v[i - 1].first);
    return w;
  };
  out->loop_area_mj = std::max(0.0, work(out->loading) - work(out->unloading));
  return {};
}

Line FitLine(const std::vector<std::pair<double, double>>& xy) {
  Line l;
  const double n = static_cast<double>(xy.size());
  if (xy.size() < 2) return l;
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (const auto& [x, y] : xy) {
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
  }
  const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n, cxy = sxy - sx * sy / n;
  if (vx <= 0) return l;
  l.slope = cxy / vx;
  l.intercept = (sy - l.slope * sx) / n;
  l.r2 = vy > 0 ? cxy * cxy / (vx * vy) : 1;
  return l;
}

}  // namespace palpa::calibration
