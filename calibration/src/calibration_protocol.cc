// The thesis protocol's settings and what its hysteresis sweep can fit (the run itself:
// calibration_run.cc).
#include "palpa/calibration/calibration_protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "palpa/calibration/play_operators.h"
#include "palpa/calibration/quality_checks.h"
#include "palpa/core/compensator.h"

namespace palpa::calibration {

ProtocolOptions QuickProtocol() {
  ProtocolOptions o;
  o.dwell_s = 0.5;
  o.contact.speed_mm_s = 1.0;
  o.press_depth_mm = 2;
  o.press_speed_mm_s = 2;
  o.sweep_press_speed_mm_s = 2;
  o.repeats = 2;
  o.biases_kpa = {0, 20};
  o.vacuums_kpa = {0, -100};
  // 10 kPa steps: 53 and 39 readings where api(8) needs 28 and pi(8) 20, so the fit has readings
  // to spare (at 20 kPa api(8) had exactly its 28 and followed the sweep's noise).
  o.pneumatic_sweep = SweepPlan{100000, 10000, 2};
  o.jamming_sweep = SweepPlan{100000, 10000, 1};
  o.correction_points = 4;
  o.default_operators = 8;
  return o;
}

SweepCapacity SweepFor(const ProtocolOptions& o, bool jamming) {
  SweepCapacity c;
  c.plan = jamming ? o.jamming_sweep : o.pneumatic_sweep;
  const std::vector<double> drives = SweepDrives(c.plan);
  c.points = drives.size();
  c.pi_operators = MaxOperators(protocol::CompensatorKind::kPrandtlIshlinskii, c.points);
  c.api_operators = MaxOperators(protocol::CompensatorKind::kAsymmetricPi, c.points);
  c.told_apart = OperatorsToldApart(drives, c.plan.drive_max, core::kMaxPlayOperators);
  c.operators = o.compensator_operators > 0
                    ? o.compensator_operators
                    : std::max(1, std::min(o.default_operators, c.told_apart));
  return c;
}

std::string SweepCapacity::Describe(std::optional<protocol::CompensatorKind> kind) const {
  const std::string n = "(" + std::to_string(operators) + ")";
  std::string fitting = !kind ? "pi" + n + " and api" + n + ", keeping the better"
                        : *kind == protocol::CompensatorKind::kAsymmetricPi ? "api" + n
                                                                            : "pi" + n;
  if (operators > told_apart) {
    fitting += " (its steps tell only " + std::to_string(told_apart) + " operators apart)";
  }
  char text[160];
  std::snprintf(text, sizeof(text),
                "%zu readings in %g kPa steps (pi up to %d operators, api up to %d; its steps tell "
                "%d apart): fitting ",
                points, plan.step / 1000, pi_operators, api_operators, told_apart);
  return text + fitting;
}

std::string SweepCapacity::Refusal(std::optional<protocol::CompensatorKind> kind) const {
  using protocol::CompensatorKind;
  const std::string n = "(" + std::to_string(operators) + ")";
  auto too_short = [&](CompensatorKind k, const std::string& name, int most) {
    return name + n + " needs " + std::to_string(MinSweepPoints(k, operators)) +
           " sweep readings; this sweep has " + std::to_string(points) + " (" + name + " up to " +
           std::to_string(most) + ")";
  };
  const bool pi = operators <= pi_operators, api = operators <= api_operators;
  if (kind == CompensatorKind::kPrandtlIshlinskii && !pi)
    return too_short(*kind, "pi", pi_operators);
  if (kind == CompensatorKind::kAsymmetricPi && !api) return too_short(*kind, "api", api_operators);
  if (!kind && !pi && !api) {
    return "neither pi" + n + " nor api" + n + ": " +
           too_short(CompensatorKind::kPrandtlIshlinskii, "pi", pi_operators);
  }
  return {};
}

}  // namespace palpa::calibration
