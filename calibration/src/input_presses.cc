// Pen presses on a force sensor: tare lifted, then each press taken once the pen's level and the
// sensor's force have both held still, and the next one asked for at another level.
#include "palpa/calibration/input_presses.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace palpa::calibration {
namespace {

struct Reading {
  double t, level, force;
};

/// Peak-to-peak of a member over the readings.
template <typename F>
double Spread(const std::deque<Reading>& w, F get) {
  double lo = get(w.front()), hi = lo;
  for (const Reading& r : w) lo = std::min(lo, get(r)), hi = std::max(hi, get(r));
  return hi - lo;
}

}  // namespace

host::Result<std::vector<host::Press>> CollectPresses(
    PenLevels& pen, ForceSensor& sensor, RigTime& time, const PressOptions& o,
    const std::function<void(const std::string&)>& say) {
  using Presses = host::Result<std::vector<host::Press>>;
  const double end = time.Now() + o.timeout_s;
  PenState state;
  // One step: the pen's next report (or its last state), and the sensor's reading now.
  const auto step = [&](double* force) -> host::Outcome {
    auto next = pen.Next(10);
    if (!next.ok()) return next;
    if (next.value) state = *next.value;
    return sensor.Read(force);
  };
  const auto out_of_time = [&](size_t taken) {
    return Presses(Status::kUnavailable, "pen calibration: time ran out after " +
                                             std::to_string(taken) + " of " +
                                             std::to_string(o.presses) + " presses");
  };
  say("lift the pen off the force sensor");
  double force = 0;
  for (;;) {
    if (host::Outcome s = step(&force); !s.ok()) return s;
    if (!state.touching) break;
    if (time.Now() > end) return out_of_time(0);
  }
  if (host::Outcome t = sensor.Tare(); !t.ok()) return t;
  std::vector<host::Press> presses;
  while (presses.size() < o.presses) {
    say("press " + std::to_string(presses.size() + 1) + " of " + std::to_string(o.presses) +
        ": press the pen on the sensor and hold it still" +
        (presses.empty() ? "" : ", harder or lighter than before"));
    std::deque<Reading> window;
    std::optional<host::Press> taken;
    while (!taken) {
      if (time.Now() > end) return out_of_time(presses.size());
      if (host::Outcome s = step(&force); !s.ok()) return s;
      if (!state.touching || force < o.min_force_n) {
        window.clear();
        continue;
      }
      const double now = time.Now();
      window.push_back({now, state.level, force});
      while (window.size() > 2 && now - window[1].t >= o.steady_s) window.pop_front();
      if (now - window.front().t < o.steady_s) continue;
      if (Spread(window, [](const Reading& r) { return r.level; }) > o.level_tolerance ||
          Spread(window, [](const Reading& r) { return r.force; }) >
              o.force_tolerance_n + o.force_tolerance_share * force)
        continue;
      double level = 0, f = 0;
      for (const Reading& r : window) level += r.level, f += r.force;
      taken = host::Press{level / window.size(), f / window.size()};
    }
    const auto near = std::find_if(presses.begin(), presses.end(), [&](const host::Press& p) {
      return std::fabs(p.level - taken->level) < o.distinct_levels;
    });
    char line[160];
    if (near != presses.end()) {
      std::snprintf(line, sizeof(line),
                    "level %.0f is within %.0f of press %zu's: lift, then press harder or lighter",
                    taken->level, o.distinct_levels,
                    static_cast<size_t>(near - presses.begin()) + 1);
    } else {
      presses.push_back(*taken);
      std::snprintf(line, sizeof(line), "press %zu: level %.0f, %.3f N — lift the pen",
                    presses.size(), taken->level, taken->force_n);
    }
    say(line);
    while (state.touching) {
      if (time.Now() > end) return out_of_time(presses.size());
      if (host::Outcome s = step(&force); !s.ok()) return s;
    }
  }
  return presses;
}

}  // namespace palpa::calibration
