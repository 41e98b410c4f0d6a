// Host loss at full size: 1 000 kills of a host process mid-stream, judged from the board's side
// and the plant's truth. Prints the tally and the distribution.
//   palpa_host_loss_bench [TRIALS]
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "host_loss.h"

namespace {

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(p * static_cast<double>(v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  const int trials = argc > 1 ? std::atoi(argv[1]) : 1000;
  const auto r = palpa::testing::RunHostLossTrials(trials, 7, 4.0);
  if (!r.error.empty()) {
    std::fprintf(stderr, "host loss: %s\n", r.error.c_str());
    return 1;
  }
  std::printf(
      "== host loss: %d kills of a host process mid-stream (palpa-sim thesis-pneumatic-3, 80 kPa, "
      "--speed 4) ==\n",
      r.trials);
  std::printf(
      "  safe command written within timeout + 1 tick: %d / %d (after the last host frame: p50 "
      "%.1f ms, max %.1f ms; "
      "timeout 100 ms)\n",
      r.safe_in_time, r.trials, Percentile(r.safe_after_ms, 0.5), Percentile(r.safe_after_ms, 1.0));
  std::printf(
      "  every chamber below 5 %% F.S. within timeout + 300 ms: %d / %d (p50 %.1f ms, max %.1f "
      "ms)\n",
      r.vented_in_time, r.trials, Percentile(r.vented_after_ms, 0.5),
      Percentile(r.vented_after_ms, 1.0));
  std::printf("  host_silence latched (a killed host cannot close its session): %d / %d\n",
              r.host_silence, r.trials);
  std::printf(
      "  attempts run again (the host was starved and the board went safe before the kill): %d;"
      " safe state never seen: %d\n",
      r.not_pressurised, r.not_observed);
  return r.safe_in_time == r.trials && r.vented_in_time == r.trials && r.host_silence == r.trials
             ? 0
             : 1;
}
