// Force readings clear of contact: means, the sensor's zero and the vented surface.
#include "palpa/calibration/procedures.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "palpa/calibration/quality_checks.h"
#include "procedure_support.h"

namespace palpa::calibration {

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

}  // namespace palpa::calibration
