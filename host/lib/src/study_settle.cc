// The settle rule and the telemetry clock behind it.
#include "study_settle.h"

#include <chrono>
#include <cmath>

#include "palpa/host/chamber_tube.h"
#include "palpa/host/stiffness_map.h"

namespace palpa::host {

SettleRule::SettleRule(std::vector<SettleLine> lines, double tolerance_pa, double band_pa,
                       double hold_s)
    : lines_(std::move(lines)), tolerance_pa_(tolerance_pa), band_pa_(band_pa), hold_s_(hold_s) {
  for (const SettleLine& l : lines_) tube_k_.push_back(TubeConstant(l.kind, l.tau_s));
}

void SettleRule::Restart() {
  // The chamber estimates run on: a restarted rule still knows where each chamber was.
  within_since_.reset();
  settled_.reset();
  steady_.clear();
}

void SettleRule::Add(double t_s, const std::vector<double>& outlet_pa,
                     const std::vector<double>& setpoint_pa) {
  if (!started_) {
    chamber_pa_.assign(lines_.size(), 0);
    for (size_t k = 0; k < lines_.size(); ++k) chamber_pa_[k] = outlet_pa[lines_[k].line];
    started_ = true;
    last_t_ = t_s;
  }
  const double dt = std::max(0.0, t_s - last_t_);
  last_t_ = t_s;
  bool near = true;
  std::vector<double> outlets;
  for (size_t k = 0; k < lines_.size(); ++k) {
    const double outlet = outlet_pa[lines_[k].line];
    // The chamber behind the outlet through the tube, as the board estimates it, per tick: a
    // deep vacuum's chamber follows slower than a shallow one's.
    chamber_pa_[k] = TubeChamberAfter(chamber_pa_[k], outlet, tube_k_[k], dt);
    near = near && std::fabs(outlet - setpoint_pa[lines_[k].line]) <= band_pa_ &&
           std::fabs(chamber_pa_[k] - outlet) <= tolerance_pa_;
    outlets.push_back(outlet);
  }
  if (settled_) return;
  if (!near) {
    Restart();
    return;
  }
  // Steady: every outlet within the tolerance of itself since within_since_; an older sample
  // that is not leaves, and the hold starts again after it.
  steady_.emplace_back(t_s, outlets);
  for (size_t k = 0; k < outlets.size(); ++k) {
    auto out_of_band = [&] {
      double lo = outlets[k], hi = outlets[k];
      for (const auto& [t, o] : steady_) lo = std::min(lo, o[k]), hi = std::max(hi, o[k]);
      return hi - lo > tolerance_pa_;
    };
    while (steady_.size() > 1 && out_of_band()) steady_.pop_front();
  }
  within_since_ = steady_.front().first;
  if (t_s - *within_since_ >= hold_s_) settled_ = within_since_;
}

TelemetryClock::TelemetryClock(Device& device, SettleRule rule, std::function<bool()> stop)
    : device_(device), rule_(std::move(rule)), stop_(std::move(stop)) {
  subscription_ = device_.Subscribe([this](const TelemetryFrame& f) { Take(f); });
}

TelemetryClock::~TelemetryClock() { device_.Unsubscribe(subscription_); }

void TelemetryClock::Take(const TelemetryFrame& f) {
  const protocol::Telemetry& t = f.telemetry;
  const protocol::HelloReply board = device_.info();
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<double> outlet(t.line_count), setpoint(t.line_count);
  for (uint8_t i = 0; i < t.tick_count; ++i) {
    for (uint8_t l = 0; l < t.line_count; ++l) {
      const protocol::LineSample& s = t.samples[static_cast<size_t>(i) * t.line_count + l];
      outlet[l] = LinePressurePa(board.lines[l], s);
      setpoint[l] = s.setpoint_pa;
    }
    now_s_ = 1e-6 * static_cast<double>(t.first_sample_us + uint64_t{i} * t.sample_interval_us);
    rule_.Add(now_s_, outlet, setpoint);
  }
  changed_.notify_all();
}

double TelemetryClock::now_s() {
  std::unique_lock<std::mutex> lock(mutex_);
  // Before the first frame: wait for it (a second of wall time at most).
  changed_.wait_for(lock, std::chrono::seconds(1), [&] { return now_s_ >= 0; });
  return now_s_;
}

void TelemetryClock::Wait(double seconds) {
  const double until = now_s() + seconds;
  std::unique_lock<std::mutex> lock(mutex_);
  // A board that stops reporting for 2 s of wall time is gone: the caller finds out next.
  while (now_s_ < until && !stopped()) {
    if (!changed_.wait_for(lock, std::chrono::seconds(2),
                           [&] { return now_s_ >= until || stopped(); }))
      return;
  }
}

std::optional<double> TelemetryClock::WaitSettled(double timeout_s) {
  const double until = now_s() + timeout_s;
  std::unique_lock<std::mutex> lock(mutex_);
  rule_.Restart();
  while (!rule_.settled_s() && now_s_ < until && !stopped()) {
    if (!changed_.wait_for(lock, std::chrono::seconds(2),
                           [&] { return rule_.settled_s() || now_s_ >= until || stopped(); }))
      break;
  }
  return rule_.settled_s();
}

}  // namespace palpa::host
