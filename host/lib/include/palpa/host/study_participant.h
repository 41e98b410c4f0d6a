// A simulated participant, for testing a study end to end: it feels the true output under each
// finger (the simulated board's truth channel stands for the fingertip) through a stiffness
// discrimination model — Weber's law with a 15 % fraction by default, seeded noise — and answers.
#pragma once

#include <random>
#include <vector>

#include "palpa/host/sim_truth.h"
#include "palpa/host/study_runner.h"

namespace palpa::host {

struct SimulatedParticipantOptions {
  /// The difference threshold as a fraction of the intensity: two values this far apart are told
  /// apart 75 % of the time when felt at once.
  double weber = 0.15;
  /// Noise at the bottom of the scale (output units: mm, N/mm), where a fraction of nothing is
  /// nothing: a 0 mm finger is not felt as exactly 0.
  double floor = 0.02;
  /// Values felt one after another are compared from memory: the noise is this many times larger.
  double memory = 1.5;
  /// Board seconds spent on a finger in a sequential block before moving on, and exploring before
  /// answering (a log-normal time around it, spread 30 %).
  double feel_s = 0.3, explore_s = 0.6;
  uint32_t seed = 1;
  /// Stop (a cancelled answer) at this trial index; −1: never.
  int stop_at = -1;
};

class SimulatedParticipant final : public StudyParticipant {
 public:
  SimulatedParticipant(TruthReader& truth, SimulatedParticipantOptions options);
  void Feel(const TrialPrompt& trial, int finger, BoardClock& clock, double until_s) override;
  Result<StudyAnswer> Answer(const TrialPrompt& trial, BoardClock& clock) override;
  void Refused(const std::string&) override { ++refused_; }
  bool Break(int, int) override {
    ++breaks_;
    return true;
  }
  int refused() const { return refused_; }
  int breaks() const { return breaks_; }
  /// What it felt on the last trial, per finger (output units, noise included).
  const std::vector<double>& felt() const { return felt_; }

 private:
  double Perceive(double truth, bool from_memory);
  std::vector<double> Truth();
  SimulatedParticipantOptions o_;
  TruthReader& truth_;
  std::mt19937_64 rng_;
  std::vector<double> felt_;
  int refused_ = 0, breaks_ = 0;
};

}  // namespace palpa::host
