// Guarded motion and contact detection: every move watched, the surface found by its force.
#include "palpa/calibration/procedures.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "palpa/host/fault_text.h"
#include "procedure_support.h"

namespace palpa::calibration {
namespace {

/// The last stretch onto a surface is crept at the thesis's indentation speed, however fast the
/// approach (see FindSurface).
constexpr double kFinalApproachMmS = 0.1;
/// A stage that stops on force and stands further above its floor than this stopped on contact.
constexpr double kStopShortMm = 0.002;

}  // namespace

std::string Num(double v, int digits) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.*g", digits, v);
  return b;
}

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

namespace {

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

}  // namespace

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

}  // namespace palpa::calibration
