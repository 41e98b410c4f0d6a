// Host-loss trials: a host process drives palpa-sim and is killed mid-stream; the board's side
// (and the plant's truth) must show the safe state within the timeout and the chambers vented.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace palpa::testing {

struct HostLossResult {
  int trials = 0;
  int safe_in_time = 0;    ///< safe command written within timeout + 1 tick (+1 ms truth sampling)
  int vented_in_time = 0;  ///< every chamber below 5 % F.S. within timeout + settling (300 ms)
  int host_silence = 0;    ///< host_silence latched: a killed host cannot close its session
  std::vector<double> safe_after_ms;  ///< from the last host frame to the safe command, board time
  std::vector<double> vented_after_ms;  ///< from the last host frame to < 5 % F.S.
  int not_pressurised = 0;  ///< attempts whose chambers never filled before the kill (run again)
  int not_observed = 0;     ///< trials where the safe state or the venting was never seen
  std::string error;        ///< set when the run itself failed
};

/// Runs `trials` kills of a host process against one palpa-sim (thesis-pneumatic-3, 80 kPa on every
/// line) at `speed`, with kill times drawn from `seed`. Must be called before the calling process
/// starts any thread (it forks).
HostLossResult RunHostLossTrials(int trials, uint32_t seed, double speed);

}  // namespace palpa::testing
