// Settling, overshoot and steady-state error of raw steps on one line of a simulated board, in
// virtual time, against the true chamber pressure; and the plant's fastest step as the bound.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <tuple>
#include <vector>

#include "palpa/core/board_configs.h"
#include "palpa/hal/sim/fastest_step.h"
#include "raw_line_session.h"

namespace palpa::bench {

inline constexpr double kNever = std::numeric_limits<double>::infinity();

/// One step's figures. Settling: within the band for good, from the command (kNever: not within
/// the dwell).
struct StepFigures {
  double settle_ms = kNever;
  double overshoot_pa = 0;  ///< beyond the target in the step's direction (true chamber)
  double error_pa = 0;      ///< steady state: mean chamber − target over the dwell's last 200 ms
  double abs_error_pa = 0;  ///< mean |chamber − target| over the whole dwell
  int crossings = 0;       ///< times the chamber went from beyond the band on one side to the other
  bool saturated = false;  ///< the line said `saturated` during the step
};

/// The settling band: 2 % of the step, at least 0.5 kPa.
inline double Band(double from_pa, double to_pa) {
  return std::max(0.02 * std::fabs(to_pa - from_pa), 500.0);
}

/// Commands `to_pa` on `line` (the line sitting at `from_pa`; `extra` setpoints ride along) and
/// runs `dwell_ms`, reading the true chamber pressure every millisecond.
inline StepFigures RunStep(RawLineSession& s, uint8_t line, double from_pa, double to_pa,
                           int dwell_ms) {
  s.Set({{line, static_cast<int32_t>(to_pa)}});
  StepFigures f;
  const double band = Band(from_pa, to_pa), direction = to_pa >= from_pa ? 1 : -1;
  int last_outside = 0, tail = 0, side = 0;
  double sum_tail = 0, sum_abs = 0;
  for (int ms = 1; ms <= dwell_ms; ++ms) {
    s.Tick();
    const double chamber = s.Chamber(line);
    if (std::fabs(chamber - to_pa) > band) {
      last_outside = ms;
      const int now = chamber > to_pa ? 1 : -1;
      if (side != 0 && now != side) ++f.crossings;
      side = now;
    }
    f.saturated = f.saturated || (s.Status(line) & protocol::line_status::kSaturated) != 0;
    f.overshoot_pa = std::max(f.overshoot_pa, direction * (chamber - to_pa));
    sum_abs += std::fabs(chamber - to_pa);
    if (ms > dwell_ms - 200) {
      sum_tail += chamber - to_pa;
      ++tail;
    }
  }
  f.settle_ms = last_outside >= dwell_ms ? kNever : last_outside;
  f.error_pa = sum_tail / tail;
  f.abs_error_pa = sum_abs / dwell_ms;
  return f;
}

/// The plant's own fastest step for the transition on the line's kind (ms to settle), and the
/// issue's goal for it: max(150 ms, 1.2 × fastest).
/// Remembered per transition: each is a simulation of its own at 0.1 ms.
inline double FastestMs(protocol::LineKind kind, double from_pa, double to_pa) {
  static std::map<std::tuple<protocol::LineKind, double, double>, double> known;
  const auto key = std::make_tuple(kind, from_pa, to_pa);
  const auto found = known.find(key);
  if (found != known.end()) return found->second;
  const double ms =
      1000.0 * sim::FastestStep(sim::NominalRegulatorSetup(kind), static_cast<float>(from_pa),
                                static_cast<float>(to_pa))
                   .settle_s;
  return known[key] = ms;
}
inline double GoalMs(double fastest_ms) { return std::max(150.0, 1.2 * fastest_ms); }

/// The q-quantile (nearest rank) of `v`; infinities sort last.
inline double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[rank == 0 ? 0 : rank - 1];
}

}  // namespace palpa::bench
