// Regulator static correction: a line's sensor reading over its range, rising and falling.
#include "palpa/calibration/procedures.h"

#include <cmath>
#include <vector>

namespace palpa::calibration {

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

}  // namespace palpa::calibration
