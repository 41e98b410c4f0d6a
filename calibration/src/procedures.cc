// Guarded motion, contact detection, regulator correction, deformation sweeps and presses.
#include "palpa/calibration/procedures.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "palpa/calibration/quality_checks.h"
#include "palpa/host/link.h"

namespace palpa::calibration {
namespace {

/// The last stretch onto a surface is crept at the thesis's indentation speed, however fast the
/// approach (see FindSurface).
constexpr double kFinalApproachMmS = 0.1;
/// A stage that stops on force and stands further above its floor than this stopped on contact.
constexpr double kStopShortMm = 0.002;

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.3g", v);
  return b;
}

/// One look at the rig while something moves: force, position, board faults.
RigStatus Watch(Rig& rig, double* force, double* position) {
  RigStatus s = rig.force.Read(force);
  if (!s.ok()) return RigStatus::Fail(s.status, "force sensor lost: " + s.message);
  s = rig.stage.Position(position);
  if (!s.ok()) return RigStatus::Fail(s.status, "stage lost: " + s.message);
  if (*force > rig.limits.max_force_n) {
    return RigStatus::Fail(Status::kOutOfRange, "force " + Num(*force) + " N above the limit of " +
                                                    Num(rig.limits.max_force_n) + " N");
  }
  if (*position < rig.limits.min_position_mm - 0.01 ||
      *position > rig.limits.max_position_mm + 0.01) {
    return RigStatus::Fail(Status::kOutOfRange,
                           "stage at " + Num(*position) + " mm, outside its limits");
  }
  uint32_t faults = 0;
  s = rig.board.Faults(&faults);
  if (!s.ok()) return RigStatus::Fail(s.status, "board lost: " + s.message);
  if (faults != 0)
    return RigStatus::Fail(Status::kFaulted, "board fault: " + host::FaultNames(faults));
  return {};
}

}  // namespace

RigStatus AbortSafe(Rig& rig, Status status, const std::string& why) {
  rig.stage.Stop();
  rig.stage.MoveTo(rig.limits.retract_mm, 2.0);  // away from the finger before anything else
  rig.board.VentAll();
  for (int i = 0; i < 2000; ++i) {  // wait for the retract, boundedly
    bool moving = false;
    if (!rig.stage.Moving(&moving).ok() || !moving) break;
    rig.time.Wait(0.01);
  }
  return RigStatus::Fail(status, why);
}

RigStatus GuardedMove(Rig& rig, double mm, double speed_mm_s, double poll_s) {
  if (mm < rig.limits.min_position_mm || mm > rig.limits.max_position_mm) {
    return AbortSafe(rig, Status::kOutOfRange,
                     "move to " + Num(mm) + " mm refused: outside the stage's limits");
  }
  RigStatus s = rig.stage.MoveTo(mm, speed_mm_s);
  if (!s.ok()) return AbortSafe(rig, s.status, "stage: " + s.message);
  for (;;) {
    double force = 0, position = 0;
    s = Watch(rig, &force, &position);
    if (!s.ok()) return AbortSafe(rig, s.status, s.message);
    bool moving = false;
    s = rig.stage.Moving(&moving);
    if (!s.ok()) return AbortSafe(rig, s.status, "stage lost: " + s.message);
    if (!moving) return {};
    rig.time.Wait(poll_s);
  }
}

/// Creeps down towards `floor_mm` at `speed_mm_s` until the force reaches the threshold; returns
/// the position at contact and `clear_mm`, a height the stage passed before its last reading
/// clear of contact was taken (so above where the contact began: the position read at the poll
/// before that reading). A stage that stops on force stops itself at the threshold, and the
/// contact is where it stopped, however late the host looks; otherwise the host stops it when it
/// sees the force, and the contact is the position read then.
RigStatus CreepToContact(Rig& rig, double floor_mm, double speed_mm_s, const ContactOptions& o,
                         double* contact_mm, double* clear_mm) {
  double before_last = 0, last = 0;
  RigStatus s = rig.stage.Position(&last);
  if (!s.ok()) return AbortSafe(rig, s.status, "stage lost: " + s.message);
  before_last = last;
  const bool stage_stops = rig.stage.stops_on_force();
  s = stage_stops ? rig.stage.MoveUntilForce(floor_mm, speed_mm_s, o.threshold_n)
                  : rig.stage.MoveTo(floor_mm, speed_mm_s);
  if (!s.ok()) return AbortSafe(rig, s.status, "stage: " + s.message);
  const double poll = 0.001;  // one force reading per millisecond: 0.1 µm of travel at 0.1 mm/s
  for (;;) {
    double force = 0, position = 0;
    s = Watch(rig, &force, &position);
    if (!s.ok()) return AbortSafe(rig, s.status, s.message);
    bool moving = false;
    if (stage_stops) {
      s = rig.stage.Moving(&moving);
      if (!s.ok()) return AbortSafe(rig, s.status, "stage lost: " + s.message);
      if (!moving) {
        s = rig.stage.Position(&position);  // stopped: where it stopped, whenever it is read
        if (!s.ok()) return AbortSafe(rig, s.status, "stage lost: " + s.message);
        // Stopped short of the floor: by its force limit (a stage stops early for nothing else).
        if (position <= floor_mm + kStopShortMm)
          return AbortSafe(rig, Status::kUnavailable,
                           "no contact down to " + Num(floor_mm) + " mm");
        *contact_mm = position;
        *clear_mm = before_last;
        return {};
      }
    } else if (force >= o.threshold_n) {
      rig.stage.Stop();
      *contact_mm = position;
      *clear_mm = before_last;
      return {};
    }
    before_last = last;
    last = position;
    if (!stage_stops) {
      rig.stage.Moving(&moving);
      if (!moving)
        return AbortSafe(rig, Status::kUnavailable, "no contact down to " + Num(floor_mm) + " mm");
    }
    rig.time.Wait(poll);
  }
}

RigStatus FindSurface(Rig& rig, double expected_mm, const ContactOptions& o, double* surface_mm) {
  RigStatus s = GuardedMove(rig, expected_mm + o.approach_mm, o.fast_mm_s);
  if (!s.ok()) return s;
  // Already touching (the surface rose): back off until clear, then creep down onto it.
  double start = expected_mm + o.approach_mm;
  for (double force = 1e9; force >= o.threshold_n;) {
    s = rig.force.Read(&force);
    if (!s.ok()) return AbortSafe(rig, s.status, "force sensor lost: " + s.message);
    if (force < o.threshold_n) break;
    if (start + 0.5 > rig.limits.max_position_mm) {
      // Far above any surface: unless something touches the indenter, the reading is its zero.
      return AbortSafe(rig, Status::kUnavailable,
                       "still in contact at the stage's upper limit: the force sensor reads " +
                           Num(1000 * force) + " mN at " + Num(start) + " mm, " +
                           Num(start - expected_mm) +
                           " mm above the surface expected; if nothing touches the indenter "
                           "there, the sensor's zero has walked past the contact threshold (" +
                           Num(1000 * o.threshold_n) + " mN)");
    }
    start += 0.5;
    s = GuardedMove(rig, start, o.fast_mm_s);
    if (!s.ok()) return s;
  }
  expected_mm = start - o.approach_mm;
  const double floor = std::max(rig.limits.min_position_mm, expected_mm - 2.0);
  double contact = 0, clear = 0;
  s = CreepToContact(rig, floor, o.speed_mm_s, o, &contact, &clear);
  if (!s.ok()) return s;
  if (o.speed_mm_s > kFinalApproachMmS) {
    // The host sees contact only with its next reading, and a busy host later still, by which
    // time the moving stage is deeper (30 µm at 1 mm/s for a reading 30 ms late; a stage that
    // stops on force is not, but its filter lags with the speed). A fast approach only finds
    // where the surface is; the stage goes back above it and creeps the last stretch at the
    // thesis's speed, where the same lateness costs a tenth as much. Back above, the contact
    // loads afresh, as a granular surface must (it unloads along another curve).
    constexpr double kMarginMm = 0.01;  // for a clear reading that was noise
    // A stage that stopped on force stopped where the force reached the threshold, whenever the
    // host looked: it backs off a fixed distance from there, clear of a soft contact (the
    // simulated film's reaches the threshold 33 µm in), so the run is the same however late the
    // host's readings came (from a polled position it would not be).
    constexpr double kBackOffMm = 0.05;
    double above = rig.stage.stops_on_force() ? contact + kBackOffMm : clear + kMarginMm;
    for (int tries = 0;; ++tries) {
      s = GuardedMove(rig, above, o.fast_mm_s);
      if (!s.ok()) return s;
      double force = 0;
      s = rig.force.Read(&force);
      if (!s.ok()) return AbortSafe(rig, s.status, "force sensor lost: " + s.message);
      if (force < o.threshold_n) break;
      if (tries == 4) {
        return AbortSafe(rig, Status::kUnavailable,
                         "still in contact (" + Num(force) + " N) at " + Num(above) +
                             " mm, well above where contact was seen (" + Num(contact) + " mm)");
      }
      above += 0.1;
    }
    s = CreepToContact(rig, floor, kFinalApproachMmS, o, &contact, &clear);
    if (!s.ok()) return s;
  }
  *surface_mm = contact;
  return GuardedMove(rig, contact + o.approach_mm, o.fast_mm_s);
}

RigStatus ReadForceMean(Rig& rig, int count, double* mean_n, double* rms_n) {
  std::vector<double> readings;
  for (int i = 0; i < count; ++i) {
    double force = 0;
    const RigStatus s = rig.force.Read(&force);
    if (!s.ok()) return AbortSafe(rig, s.status, "force sensor lost: " + s.message);
    readings.push_back(force);
    rig.time.Wait(0.01);
  }
  double mean = 0, square = 0;
  for (double f : readings) mean += f / count;
  for (double f : readings) square += (f - mean) * (f - mean) / count;
  *mean_n = mean;
  if (rms_n != nullptr) *rms_n = std::sqrt(square);
  return {};
}

RigStatus ReadClearForce(Rig& rig, double fast_mm_s, double* force_n, double* rms_n) {
  const RigStatus s = GuardedMove(rig, rig.limits.retract_mm, fast_mm_s);
  return s.ok() ? ReadForceMean(rig, 10, force_n, rms_n) : s;
}

RigStatus CheckZeroBefore(Rig& rig, const ContactOptions& o, const std::string& before,
                          double* clear_n, bool* walked) {
  *clear_n = std::numeric_limits<double>::quiet_NaN();
  *walked = false;
  double clear = 0, rms = 0;
  const RigStatus s = ReadClearForce(rig, o.fast_mm_s, &clear, &rms);
  if (!s.ok()) return s;
  *clear_n = clear;
  *walked = std::fabs(clear) >= o.threshold_n && rms <= kNoiseLimitClasses * rig.force_noise_n;
  if (!*walked) return {};
  // Named as the force_zero check names its failures: the stop is that check, come early.
  return AbortSafe(rig, Status::kUnavailable,
                   "force_zero: the force sensor's zero has walked: it reads " + Num(1000 * clear) +
                       " mN clear of everything (the indenter retracted to " +
                       Num(rig.limits.retract_mm) + " mm), at or over the contact threshold of " +
                       Num(1000 * o.threshold_n) + " mN, before the " + before +
                       "; a surface search would read contact anywhere. Let the sensor settle: "
                       "a resumed run takes the zero again");
}

RigStatus ZeroOnVentedSurface(Rig& rig, uint8_t finger, const ContactOptions& o, double* zero_mm,
                              double* noise_n) {
  RigStatus s = rig.board.SetDrive(finger, 0, 0);
  if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
  s = GuardedMove(rig, rig.limits.retract_mm, o.fast_mm_s);
  if (!s.ok()) return s;
  rig.time.Wait(2.0);  // vented and settled, indenter clear: the force sensor's zero
  s = rig.force.Tare();
  if (!s.ok()) return AbortSafe(rig, s.status, "force sensor: " + s.message);
  if (noise_n != nullptr) {
    double mean = 0;
    s = ReadForceMean(rig, 100, &mean, noise_n);
    if (!s.ok()) return s;
  }
  return FindSurface(rig, 0, o, zero_mm);
}

RigStatus RegulatorCorrection(Rig& rig, uint8_t finger, uint8_t line, int points, double dwell_s,
                              std::vector<protocol::CorrectionPoint>* out) {
  const bool jamming = rig.board.jamming(finger);
  const bool vacuum = jamming && line == rig.board.driven_line(finger);
  double range = 0;
  RigStatus s = rig.board.LineRangeKpa(line, &range);
  if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
  s = rig.board.SetTrim(line, false);
  if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
  std::vector<double> commands, rising(points), falling(points);
  // From 10 % (above the regulator's minimum set pressure) to 90 % of the line's range.
  for (int i = 0; i < points; ++i) commands.push_back(range * (0.1 + 0.8 * i / (points - 1)));
  auto settle = [&](double kpa, double* measured) {
    // The other line of a jamming finger at its working value: the bias at 20 kPa, vacuum released.
    RigStatus r = !jamming ? rig.board.SetDrive(finger, kpa, 0)
                  : vacuum ? rig.board.SetDrive(finger, 20, -kpa)
                           : rig.board.SetDrive(finger, kpa, 0);
    if (!r.ok()) return r;
    rig.time.Wait(dwell_s);
    uint32_t faults = 0;
    r = rig.board.Faults(&faults);
    if (!r.ok()) return r;
    if (faults != 0) return RigStatus::Fail(Status::kFaulted, "board fault during the correction");
    return rig.board.MeasuredKpa(line, measured);
  };
  for (int i = 0; i < points && s.ok(); ++i) s = settle(commands[i], &rising[i]);
  // A pressure line's falling branch from above its top point: straight after the rising sweep's
  // last point the top's falling reading is the rising one's, and a shaped step, back from its
  // overdrive, lands on the true falling branch: 0.3-0.4 kPa too high for good at 85-90 kPa.
  // Not a vacuum line's: near the pump's pressure its deep steps end on the rising branch (the
  // chamber is slower there than its model, the outlet never goes beyond; docs/performance.md).
  if (s.ok() && !vacuum) {
    double above = 0;
    s = settle(commands.back() + 0.05 * range, &above);
  }
  for (int i = points - 1; i >= 0 && s.ok(); --i) s = settle(commands[i], &falling[i]);
  rig.board.SetTrim(line, true);
  if (!s.ok()) return AbortSafe(rig, s.status, "regulator correction: " + s.message);
  out->clear();
  const double sign = vacuum ? -1 : 1;
  for (int i = 0; i < points; ++i) {
    protocol::CorrectionPoint p;
    p.command_pa = static_cast<int32_t>(std::lround(sign * commands[i] * 1000));
    p.rising_pa = static_cast<int32_t>(std::lround(rising[i] * 1000));
    p.falling_pa = static_cast<int32_t>(std::lround(falling[i] * 1000));
    out->push_back(p);
  }
  // The board takes strictly monotone curves: a reading that did not move is nudged by 1 Pa.
  for (size_t i = 1; i < out->size(); ++i) {
    auto& a = (*out)[i - 1];
    auto& b = (*out)[i];
    if (sign * (b.rising_pa - a.rising_pa) <= 0)
      b.rising_pa = a.rising_pa + static_cast<int32_t>(sign);
    if (sign * (b.falling_pa - a.falling_pa) <= 0)
      b.falling_pa = a.falling_pa + static_cast<int32_t>(sign);
  }
  return rig.board.SetDrive(finger, 0, 0);
}

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
