// Prediction: the display's half-step delay from the line's calibrated model, and a bounded
// straight-line extrapolation of the hand that falls back to none when the motion is erratic.
#include "palpa/host/scene_predict.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "number_text.h"
#include "palpa/core/board.h"
#include "palpa/core/line_pipeline.h"
#include "palpa/host/chamber_tube.h"

namespace palpa::host {

LineDynamics DynamicsOf(const protocol::ConfigureLine& line) {
  return {line.model_dead_time_us * 1e-6,
          line.model_tau_us * 1e-6,
          line.chamber_tau_us * 1e-6,
          static_cast<double>(line.overdrive_pa),
          line.kind == protocol::LineKind::kVacuum,
          static_cast<double>(line.limit_max_pa)};
}

double HalfStepTime(const protocol::ConfigureLine& configured, double step_pa) {
  // The board's own line step (MakeLineParams, StepLine: the slew limit, the shaped step's lead,
  // its overdrive held within the line's limits, the chamber estimated from the outlet through the
  // tube's law, at the board's tick) against the calibrated model as the plant: the command held
  // over each tick, its dead time, the regulator's lag, and the chamber behind the outlet through
  // the tube's law, dC/dt = k (O − C)(O + C + 2 p_atm), at a tenth of the tick. The regulator is
  // asked for the pressure the step wants: without the static correction or the trim, which
  // only make the real regulator's outlet what the model's is.
  constexpr uint32_t tick_us = core::Board::kTickUs;
  constexpr int substeps = 10;
  const double dt = tick_us * 1e-6 / substeps;
  protocol::ConfigureLine line = configured;
  line.correction_count = 0;
  line.trim_kp = 0, line.trim_ki_per_s = 0, line.trim_authority_pa = 0;
  const core::LineParams p = core::MakeLineParams(line, tick_us);
  const double signed_step =
      line.kind == protocol::LineKind::kVacuum ? -std::fabs(step_pa) : std::fabs(step_pa);
  const double target = std::clamp(signed_step, static_cast<double>(p.limit_min_pa),
                                   static_cast<double>(p.limit_max_pa));
  const double half = std::fabs(target) / 2;
  const double dead_s = line.model_dead_time_us * 1e-6, tau = line.model_tau_us * 1e-6;
  if (!(half > 0)) return dead_s;
  const double k = TubeConstant(line.kind, line.chamber_tau_us * 1e-6);
  core::LineState s;
  core::ResetLineState(p, s, 0);
  const size_t dead = static_cast<size_t>(std::lround(dead_s / dt));
  std::vector<double> delayed(dead + 1, 0.0);  // the commands of the last `dead` substeps
  double regulator = 0, chamber = 0, command = 0;
  for (size_t n = 0; n < static_cast<size_t>(10.0 / dt); ++n) {
    if (n % substeps == 0) {
      core::LineReading reading;
      reading.valid = p.has_sensor, reading.pa = static_cast<float>(regulator);
      core::LineOutput out;
      uint32_t vents = 0;
      core::StepLine(p, s, static_cast<float>(target), reading, out, &vents);
      command = out.command_pa;
    }
    delayed[n % delayed.size()] = command;
    const double in = delayed[(n + 1) % delayed.size()];  // the command `dead` substeps ago
    regulator = tau > 0 ? regulator + dt / (tau + dt) * (in - regulator) : in;
    chamber = TubeChamberAfter(chamber, regulator, k, dt);
    if (std::fabs(chamber) >= half) return (static_cast<double>(n) + 1) * dt;
  }
  return 10.0;
}

double HalfStepTime(const LineDynamics& m, double step_pa) {
  // A configuration that says no more than the dynamics: no slew limit, no dead band, a sensor
  // on the outlet (the board estimates the chamber from it), limits 0 … limit_max_pa, or from
  // the deepest vacuum on a vacuum line.
  protocol::ConfigureLine line;
  line.kind = m.vacuum ? protocol::LineKind::kVacuum : protocol::LineKind::kPressure;
  const int32_t top = static_cast<int32_t>(std::lround(m.limit_max_pa));
  line.limit_min_pa = line.command_min_pa = m.vacuum ? protocol::kMinPressurePa : 0;
  line.limit_max_pa = line.command_max_pa = top;
  line.sensor = protocol::SensorKind::kAnalog;
  line.sensor_min_pa = line.limit_min_pa, line.sensor_max_pa = top;
  line.sensor_counts_min = 0, line.sensor_counts_max = 16383;
  const auto us = [](double s) { return static_cast<uint32_t>(std::lround(s * 1e6)); };
  line.model_dead_time_us = us(m.dead_time_s);
  line.model_tau_us = us(m.regulator_tau_s);
  line.chamber_tau_us = us(m.chamber_tau_s);
  line.overdrive_pa = static_cast<int32_t>(std::clamp(m.overdrive_pa, 0.0, 100000.0));
  return HalfStepTime(line, step_pa);
}

Result<double> DisplayDelay(const protocol::ConfigureLine& line, double step_pa) {
  if (line.chamber_tau_us == 0) {
    return {Status::kUnavailable,
            "line " + std::to_string(line.line + 1) +
                " has no chamber model: its delay is unknown until it is calibrated "
                "(palpa calibrate), so nothing can be predicted for it"};
  }
  return HalfStepTime(line, step_pa);
}

double DriveForOutput(protocol::FingerKind kind, const FingerCurves& curves, double output) {
  const bool jamming = kind == protocol::FingerKind::kJamming;
  // Both curves are monotone over their drive: bisection on the magnitude 0 … 100 kPa.
  const auto at = [&](double magnitude) {
    return jamming ? StiffnessAtVacuum(curves, -magnitude)
                   : DeformationAtPressure(curves, magnitude);
  };
  const bool rising = at(100) >= at(0);
  double lo = 0, hi = 100;
  for (int k = 0; k < 50; ++k) {
    const double mid = (lo + hi) / 2;
    ((at(mid) < output) == rising ? lo : hi) = mid;
  }
  return jamming ? -(lo + hi) / 2 : (lo + hi) / 2;
}

double SceneStepPa(const SceneRenderer& r, size_t k) {
  const RenderFinger& f = r.fingers().at(k);
  return 1000 * std::fabs(DriveForOutput(f.summary.kind, f.curves, r.OutputAt(k, 1)) -
                          DriveForOutput(f.summary.kind, f.curves, r.OutputAt(k, 0)));
}

Outcome CheckPredictor(const PredictorOptions& o) {
  const auto within = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  if (!within(o.horizon_s, 0, 1))
    return Outcome::Fail(Status::kInvalidArgument,
                         "prediction horizon " + Num(o.horizon_s) + " s is outside 0 … 1 s");
  if (!within(o.window_s, 0.005, 1))
    return Outcome::Fail(Status::kInvalidArgument,
                         "prediction window " + Num(o.window_s) + " s is outside 0.005 … 1 s");
  if (!within(o.max_lead_mm, 0, 50))
    return Outcome::Fail(Status::kInvalidArgument,
                         "prediction lead " + Num(o.max_lead_mm) + " mm is outside 0 … 50 mm");
  if (!within(o.erratic_rms_mm, 0, 1e3) || !within(o.stop_speed_mm_s, 0, 1e4) ||
      !(o.max_gap_s > 0 && o.max_gap_s <= 10))
    return Outcome::Fail(Status::kInvalidArgument, "prediction thresholds out of range");
  return {};
}

const char* PredictionName(Prediction p) {
  switch (p) {
    case Prediction::kPredicted:
      return "predicted";
    case Prediction::kTooFewSamples:
      return "too few samples";
    case Prediction::kErratic:
      return "erratic";
    case Prediction::kReversing:
      return "reversing";
    case Prediction::kStopped:
      return "stopped";
    case Prediction::kLifted:
      return "lifted";
  }
  return "?";
}

namespace {

/// Least-squares velocity of x and y over samples [begin, end), and the RMS of the residuals.
struct MotionFit {
  double vx = 0, vy = 0, rms = 0;
};
MotionFit Fit(const std::deque<SceneInput>& h, size_t begin, size_t end) {
  const double n = static_cast<double>(end - begin);
  double st = 0, sx = 0, sy = 0;
  for (size_t k = begin; k < end; ++k) st += h[k].time_s, sx += h[k].x_mm, sy += h[k].y_mm;
  const double mt = st / n, mx = sx / n, my = sy / n;
  double stt = 0, stx = 0, sty = 0;
  for (size_t k = begin; k < end; ++k) {
    const double dt = h[k].time_s - mt;
    stt += dt * dt, stx += dt * (h[k].x_mm - mx), sty += dt * (h[k].y_mm - my);
  }
  MotionFit f;
  if (stt <= 0) return f;
  f.vx = stx / stt, f.vy = sty / stt;
  double ss = 0;
  for (size_t k = begin; k < end; ++k) {
    const double dt = h[k].time_s - mt;
    const double ex = h[k].x_mm - (mx + f.vx * dt), ey = h[k].y_mm - (my + f.vy * dt);
    ss += ex * ex + ey * ey;
  }
  f.rms = std::sqrt(ss / n);
  return f;
}

}  // namespace

SceneInput MotionPredictor::Next(const SceneInput& s) {
  last_lead_ = 0;
  // A new motion after a gap (or time going back): what came before says nothing of it.
  if (!history_.empty() &&
      !(s.time_s > history_.back().time_s && s.time_s - history_.back().time_s <= o_.max_gap_s))
    history_.clear();
  history_.push_back(s);
  while (history_.size() > 3 && s.time_s - history_.front().time_s > o_.window_s)
    history_.pop_front();
  while (history_.size() > 256) history_.pop_front();
  const size_t n = history_.size();
  if (!(s.force_n > 0) || !std::isfinite(s.x_mm) || !std::isfinite(s.y_mm)) {
    return Done(Prediction::kLifted, s);
  }
  if (n < 3) {
    return Done(Prediction::kTooFewSamples, s);
  }
  const MotionFit all = Fit(history_, 0, n);
  const MotionFit recent = Fit(history_, n / 2, n);
  const double speed = std::hypot(all.vx, all.vy);
  const double recent_speed = n >= 4 ? std::hypot(recent.vx, recent.vy) : speed;
  // The latest half moving against the whole window: a reversal under way (a stop is not one).
  if (n >= 4 && recent_speed >= o_.stop_speed_mm_s &&
      recent.vx * all.vx + recent.vy * all.vy <= 0) {
    return Done(Prediction::kReversing, s);
  }
  if (all.rms > o_.erratic_rms_mm || !std::isfinite(speed)) {
    return Done(Prediction::kErratic, s);
  }
  // Slowing down: the slower of the two, so a stop is not overshot by the whole window's speed.
  const double vx = recent_speed < speed ? recent.vx : all.vx;
  const double vy = recent_speed < speed ? recent.vy : all.vy;
  const double v = std::min(speed, recent_speed);
  if (v < o_.stop_speed_mm_s) {
    return Done(Prediction::kStopped, s);
  }
  const double interval = (s.time_s - history_.front().time_s) / static_cast<double>(n - 1);
  const double horizon = o_.horizon_s + interval / 2;
  double lead = v * horizon;
  const double scale = lead > o_.max_lead_mm ? o_.max_lead_mm / lead : 1.0;
  SceneInput out = s;
  out.x_mm += vx * horizon * scale;
  out.y_mm += vy * horizon * scale;
  // A sample on the tissue is not predicted off it.
  if (extent_x_ > 0 && s.x_mm >= 0 && s.x_mm <= extent_x_)
    out.x_mm = std::clamp(out.x_mm, 0.0, extent_x_);
  if (extent_y_ > 0 && s.y_mm >= 0 && s.y_mm <= extent_y_)
    out.y_mm = std::clamp(out.y_mm, 0.0, extent_y_);
  last_lead_ = std::hypot(out.x_mm - s.x_mm, out.y_mm - s.y_mm);
  return Done(Prediction::kPredicted, out);
}

SceneInput MotionPredictor::Done(Prediction p, const SceneInput& out) {
  last_ = p;
  ++counts_[static_cast<size_t>(p)];
  last_out_ = out;
  return out;
}

}  // namespace palpa::host
