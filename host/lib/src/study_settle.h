// The board's clock and the settle rule, fed by telemetry: settled when every driven line's outlet
// reading has stayed within the tolerance of itself for the hold time, near its setpoint (within
// the band a regulator's static error leaves), with its chamber — the outlet through the tube's
// law with the line's calibrated constant, as the board estimates it — caught up with it.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/host/study_runner.h"

namespace palpa::host {

/// The rule on its own, sample by sample (board time, outlet Pa, setpoint Pa per line).
class SettleRule {
 public:
  SettleRule(std::vector<SettleLine> lines, double tolerance_pa, double band_pa, double hold_s);
  /// Starts a new settle from the next tick (after a change has been applied); the chamber
  /// estimates carry on from where they were (they start at the first tick ever seen).
  void Restart();
  /// One tick: `outlet_pa` and `setpoint_pa` indexed by line number.
  void Add(double t_s, const std::vector<double>& outlet_pa,
           const std::vector<double>& setpoint_pa);
  /// The board time the display settled at: the start of the hold that completed; none yet.
  std::optional<double> settled_s() const { return settled_; }

 private:
  std::vector<SettleLine> lines_;
  double tolerance_pa_, band_pa_, hold_s_;
  std::vector<double> tube_k_;  ///< per line: the tube's constant (0: the outlet alone)
  std::vector<double> chamber_pa_;
  std::deque<std::pair<double, std::vector<double>>> steady_;  ///< (t, outlets) since within_since_
  bool started_ = false;
  double last_t_ = 0;
  std::optional<double> within_since_, settled_;
};

/// The board's clock, and the settle rule fed from the same telemetry.
class TelemetryClock final : public BoardClock {
 public:
  /// `stop`, optional: true once the session stops — every wait ends then.
  TelemetryClock(Device& device, SettleRule rule, std::function<bool()> stop = nullptr);
  ~TelemetryClock() override;
  double now_s() override;
  void Wait(double seconds) override;
  /// Restarts the rule and waits until it says settled (the board time then), or `timeout_s`
  /// of board time passes (none).
  std::optional<double> WaitSettled(double timeout_s);
  bool stopped() const { return stop_ && stop_(); }

 private:
  void Take(const TelemetryFrame& f);
  Device& device_;
  int subscription_ = 0;
  std::mutex mutex_;
  std::condition_variable changed_;
  double now_s_ = -1;
  SettleRule rule_;
  std::function<bool()> stop_;
};

}  // namespace palpa::host
