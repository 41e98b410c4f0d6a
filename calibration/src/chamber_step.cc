// The chamber's step response on the rig and its dead time + lag fit.
#include "palpa/calibration/chamber_step.h"

#include <algorithm>
#include <cmath>

#include "palpa/host/chamber_tube.h"

namespace palpa::calibration {
using host::Status;

double ChamberResponse(const ChamberFit& fit, double t) {
  if (t <= fit.dead_time_s) return 0;
  const double s = t - fit.dead_time_s, a = fit.regulator_tau_s, b = fit.tau_s;
  if (a <= 0 || b <= 0) {  // one lag, or none
    const double tau = a > 0 ? a : b;
    return tau > 0 ? 1.0 - std::exp(-s / tau) : 1.0;
  }
  if (std::fabs(a - b) < 1e-6) return 1.0 - (1.0 + s / a) * std::exp(-s / a);
  return 1.0 - (a * std::exp(-s / a) - b * std::exp(-s / b)) / (a - b);
}

ChamberFit FitChamberStep(const std::vector<std::pair<double, double>>& samples,
                          double regulator_tau_s, double noise) {
  ChamberFit best;
  double start = 0, end = 0, last_t = 0;
  int before = 0, tail = 0;
  for (const auto& [t, v] : samples) last_t = std::max(last_t, t);
  for (const auto& [t, v] : samples) {
    if (t < 0) start += v, ++before;
    if (t > last_t - 0.05) end += v, ++tail;
  }
  if (before == 0 || tail == 0) return best;
  start /= before;
  end /= tail;
  const double span = end - start;
  // A step the readings' noise could fake is no step to fit.
  if (std::fabs(span) < std::max(10.0 * noise, 1e-12)) return best;
  int n = 0;
  for (const auto& sample : samples) n += sample.first >= 0 ? 1 : 0;
  best.rms = 1e9;
  if (n == 0) return best;
  // The candidate's RMS; above `give_up` (a sum of squares no better fit can have) it stops
  // early and says so with a huge value: most of the grid is far off within the first samples.
  auto cost = [&](const ChamberFit& f, double give_up) {
    double sum = 0;
    for (const auto& [t, v] : samples) {
      if (t < 0) continue;
      const double e = (v - start) / span - ChamberResponse(f, t);
      sum += e * e;
      if (sum > give_up) return 1e9;
    }
    return std::sqrt(sum / n);
  };
  // A grid: dead time by 0.5 ms up to 50 ms; the chamber's lag none, or 0.5 ms to 2 s by 2 %.
  for (double dead = 0; dead <= 0.05; dead += 0.0005) {
    for (double tau = 0; tau <= 2.0; tau = tau == 0 ? 0.0005 : tau * 1.02) {
      const ChamberFit f{dead, regulator_tau_s, tau, 0, true};
      // A margin over the best's sum of squares, so rounding never drops a candidate it keeps.
      const double give_up = best.rms < 1e9 ? best.rms * best.rms * n * (1 + 1e-9) : HUGE_VAL;
      const double c = cost(f, give_up);
      if (c < best.rms) best = ChamberFit{dead, regulator_tau_s, tau, c, true};
    }
  }
  return best;
}

void FitTubeStep(const std::vector<std::pair<double, double>>& samples,
                 const std::vector<std::pair<double, double>>& outlet, protocol::LineKind kind,
                 ChamberFit* fit) {
  fit->outlet_tau_s = fit->outlet_rms = 0;
  if (samples.size() != outlet.size() || samples.empty()) return;
  const double last_t = samples.back().first;
  double f0 = 0, f1 = 0, o0 = 0, o1 = 0;
  int before = 0, tail = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const double t = samples[i].first;
    if (t < 0) f0 += samples[i].second, o0 += outlet[i].second, ++before;
    if (t > last_t - 0.05) f1 += samples[i].second, o1 += outlet[i].second, ++tail;
  }
  if (before == 0 || tail == 0) return;
  f0 /= before, f1 /= tail, o0 /= before, o1 /= tail;
  if (f1 == f0 || o1 == o0) return;
  // The chamber the force says, in Pa; the model's against it as a fraction of the step.
  const double scale = (o1 - o0) / (f1 - f0);
  auto cost = [&](double k) {
    double c = o0, sum = 0;
    int n = 0;
    for (size_t i = 0; i + 1 < samples.size(); ++i) {
      const double t = samples[i].first;
      if (t >= 0) {
        const double e = (c - (o0 + (samples[i].second - f0) * scale)) / (o1 - o0);
        sum += e * e, ++n;
      }
      // The outlet held over the sample, as the board's estimate takes it.
      c = host::TubeChamberAfter(c, outlet[i].second, k, samples[i + 1].first - t);
    }
    return n > 0 ? std::sqrt(sum / n) : 1e9;
  };
  // k found through the lag at the board's reference, whatever the step's own pressures: the
  // board converts the stored lag back to k there.
  double best = 1e9;
  for (double tau = 0.0005; tau <= 2.0; tau *= 1.005) {
    const double c = cost(host::TubeConstant(kind, tau));
    if (c < best) best = c, fit->outlet_tau_s = tau;
  }
  fit->outlet_rms = best;
}

RigStatus MeasureChamberStep(Rig& rig, uint8_t finger, double zero_mm, const ContactOptions& o,
                             const ChamberStepOptions& options, ChamberStep* out) {
  *out = ChamberStep{};
  const bool jamming = rig.board.jamming(finger);
  const uint8_t line = rig.board.driven_line(finger);
  // A jamming finger's bias at its working value, the step on its vacuum.
  auto drive = [&](double kpa) {
    return jamming ? rig.board.SetDrive(finger, 20, -kpa) : rig.board.SetDrive(finger, kpa, 0);
  };
  RigStatus s = rig.board.SetBareLine(line, true);
  if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
  s = drive(options.from_kpa);
  if (s.ok()) rig.time.Wait(1.0);
  double surface = 0;
  if (s.ok()) s = FindSurface(rig, zero_mm, o, &surface);
  if (!s.ok()) {
    rig.board.SetBareLine(line, false);
    return s;
  }
  const double into = jamming ? options.press_mm : options.depth_mm;
  s = GuardedMove(rig, surface - into, jamming ? 0.5 : o.speed_mm_s);
  if (s.ok()) rig.time.Wait(0.5);  // the contact settles (a granular press relaxes)
  // Readings on the rig's clock, from before the command to after_s past it.
  const double start = rig.time.Now(), command = start + options.before_s;
  bool stepped = false;
  while (s.ok() && rig.time.Now() < command + options.after_s) {
    if (!stepped && rig.time.Now() >= command) {
      s = drive(options.to_kpa);
      stepped = true;
    }
    double force = 0;
    if (s.ok()) s = rig.force.Read(&force);
    if (!s.ok()) break;
    if (force > rig.limits.max_force_n) {
      s = RigStatus::Fail(Status::kOutOfRange, "force above the rig's limit during the step");
      break;
    }
    double outlet_kpa = 0;
    s = rig.board.MeasuredKpa(line, &outlet_kpa);
    if (!s.ok()) break;
    out->samples.push_back({rig.time.Now() - command, force});
    out->outlet.push_back({rig.time.Now() - command, 1000 * outlet_kpa});
    rig.time.Wait(options.sample_s);
  }
  rig.board.SetBareLine(line, false);
  if (!s.ok()) return AbortSafe(rig, s.status, "chamber step: " + s.message);
  s = GuardedMove(rig, surface + o.approach_mm, o.fast_mm_s);
  if (!s.ok()) return s;
  const double period =
      (options.before_s + options.after_s) / std::max<size_t>(1, out->samples.size());
  if (period > 0.002) {
    out->why = "force readings every " + std::to_string(std::lround(1000 * period)) +
               " ms: a chamber's step needs 500 Hz";
  } else {
    out->fit = FitChamberStep(out->samples, options.regulator_tau_s, rig.force_noise_n);
    if (!out->fit.ok) out->why = "the force did not follow the step";
    const auto kind = jamming ? protocol::LineKind::kVacuum : protocol::LineKind::kPressure;
    if (out->fit.ok) FitTubeStep(out->samples, out->outlet, kind, &out->fit);
  }
  return rig.board.SetDrive(finger, 0, 0);
}

}  // namespace palpa::calibration
