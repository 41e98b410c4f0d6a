// The simulated participant's perception and decision.
#include "palpa/host/study_participant.h"

#include <algorithm>
#include <cmath>

namespace palpa::host {
namespace {

/// A standard normal draw from the engine's raw output (Box–Muller), the same on every library.
double Normal(std::mt19937_64& rng) {
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) / 9007199254740992.0;
  const double u2 = static_cast<double>(rng() >> 11) / 9007199254740992.0;
  return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

}  // namespace

SimulatedParticipant::SimulatedParticipant(TruthReader& truth, SimulatedParticipantOptions options)
    : o_(options), truth_(truth), rng_(options.seed) {}

std::vector<double> SimulatedParticipant::Truth() {
  TruthReader::Sample s;
  return truth_.Latest(s) ? s.outputs : std::vector<double>{};
}

double SimulatedParticipant::Perceive(double truth, bool from_memory) {
  // The difference of two perceptions is 0.6745 of its spread at 75 %: that spread is the Weber
  // fraction, shared by the two as √2.
  const double sigma = o_.weber / (0.6745 * std::sqrt(2.0)) * (from_memory ? o_.memory : 1.0);
  return truth * (1 + sigma * Normal(rng_)) + o_.floor * Normal(rng_);
}

void SimulatedParticipant::Feel(const TrialPrompt& trial, int finger, BoardClock& clock,
                                double until_s) {
  if (finger == 0) felt_.assign(static_cast<size_t>(trial.fingers), 0);
  clock.Wait(std::max(0.0, std::min(o_.feel_s, until_s - clock.now_s())));
  const std::vector<double> truth = Truth();
  if (static_cast<size_t>(finger) < truth.size())
    felt_[static_cast<size_t>(finger)] = Perceive(truth[static_cast<size_t>(finger)], true);
}

Result<StudyAnswer> SimulatedParticipant::Answer(const TrialPrompt& trial, BoardClock& clock) {
  if (trial.index == o_.stop_at) return {Status::kUnavailable, "stopped by the participant"};
  clock.Wait(o_.explore_s * std::exp(0.3 * Normal(rng_)) *
             (trial.mode == StudyMode::kSequential ? 0.3 : 1));
  if (trial.mode == StudyMode::kSimultaneous) {
    const std::vector<double> truth = Truth();
    felt_.assign(static_cast<size_t>(trial.fingers), 0);
    for (size_t f = 0; f < felt_.size() && f < truth.size(); ++f)
      felt_[f] = Perceive(truth[f], false);
  }
  StudyAnswer a;
  a.fingers.assign(static_cast<size_t>(trial.fingers), false);
  if (trial.kind == BlockKind::kStaircase) {
    const int x = trial.compared[0], y = trial.compared[1];
    a.fingers[static_cast<size_t>(
        felt_[static_cast<size_t>(x)] >= felt_[static_cast<size_t>(y)] ? x : y)] = true;
    a.tumour = true;
    return a;
  }
  // A finger is stiffer than the softest when it stands out by more than the threshold.
  const double lo = *std::min_element(felt_.begin(), felt_.end());
  for (size_t f = 0; f < felt_.size(); ++f)
    a.fingers[f] = felt_[f] - lo > o_.weber * std::fabs(lo) + 2 * o_.floor;
  a.tumour = std::count(a.fingers.begin(), a.fingers.end(), true) > 0;
  return a;
}

}  // namespace palpa::host
