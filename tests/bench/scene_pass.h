// One pass of a scene over the simulated board in virtual time (plant level 3, a held-out unit):
// each input sample rendered and sent as one SetFingerTargets, every board tick each finger's true
// output scored against the rule's target at its current position, and the edge lag at cube B.
// The board's fingers on their nominal curves, or calibrated on their rig first as palpa calibrate
// would (each line's static correction, and its chamber model uploaded: steps shaped).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "in_process_board.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/scene_render.h"
#include "steps_calibration.h"

namespace palpa::bench {

namespace ps = palpa::sim;
namespace pp = palpa::protocol;
namespace ph = palpa::host;

constexpr int kInputEveryMs = 10;
constexpr double kStartX = 20, kEndX = 100, kY = 15;

struct PassResult {
  std::vector<double> errors;  ///< |true − target| / range, every tick, every finger
  double edge_lag_mm = NAN;
};

constexpr uint32_t kUnit = 12;  // a held-out unit (actuators, regulators, sensors): not nominal

class ScenePass {
 public:
  /// `board_fingers` are the scene's, calibrated when `calibrated`.
  ScenePass(const ph::SceneRenderer& scene, bool jamming, bool calibrated,
            const std::vector<uint8_t>& board_fingers)
      : scene_(scene),
        jamming_(jamming),
        board_(testing::PlantBoardOptions(jamming ? "thesis-jamming-2" : "thesis-pneumatic-3",
                                          kUnit, kUnit, {})) {
    if (calibrated) ok_ = Calibrate(board_fingers);
  }
  /// False when the board refused a calibrated line's configuration (said on stderr).
  bool ok() const { return ok_; }

  /// A path: the input's x at each millisecond of the pass (after settling at the first).
  PassResult Pass(const std::vector<double>& path, double range_mm) {
    PassResult r;
    // Settle at the start (the first target re-homes the fingers), then the pass.
    const int settle_ms = 1500;
    const int pass_ms = static_cast<int>(path.size()) - 1;
    double previous_true = 0;
    const double edge = 54;  // cube B's near face, where finger 0 meets it
    const double dx0 = scene_.layout().fingers[0].dx_mm;  // finger 0 from the input
    const double before = Target0(edge - 3 - dx0), on = Target0(edge + 3 - dx0);
    const double half = (before + on) / 2;
    double rule_cross = NAN;
    for (int ms = -settle_ms; ms <= pass_ms; ++ms) {
      const double x = path[static_cast<size_t>(std::max(0, ms))];
      if (ms % kInputEveryMs == 0) SendTargets(x);
      board_.Run(1);
      if (ms < 0) continue;
      const auto truth = board_.sim().plant().Truth();
      const auto now = scene_.Render({0, x, kY, 1});
      for (size_t f = 0; f < now.size(); ++f) {
        const double target = now[f].mapped.target / 1000.0;
        r.errors.push_back(std::fabs(True(truth, f) - target) / range_mm);
      }
      if (std::isnan(rule_cross) && now[0].mapped.target / 1000.0 >= half) rule_cross = x + dx0;
      const double true0 = True(truth, 0);
      if (std::isnan(r.edge_lag_mm) && !std::isnan(rule_cross) && previous_true < half &&
          true0 >= half)
        r.edge_lag_mm = x + dx0 - rule_cross;
      previous_true = true0;
    }
    return r;
  }

 private:
  /// Each finger's lines as the host configures them from the finger's calibration file: the
  /// static correction, and the chamber model with the overdrive bound and no slew limit.
  bool Calibrate(const std::vector<uint8_t>& fingers) {
    const core::BoardConfig& board = board_.config();
    const UnitCalibration& u =
        CalibrationFor(kUnit, jamming_ ? "thesis-jamming-2" : "thesis-pneumatic-3", fingers);
    for (uint8_t line = 0; line < board.line_count; ++line) {
      if (u.correction[line].empty() && !u.chamber[line].ok) continue;
      pp::ConfigureLine c = board.lines[line];
      c.correction_count = static_cast<uint8_t>(u.correction[line].size());
      std::copy(u.correction[line].begin(), u.correction[line].end(), c.correction.begin());
      if (u.chamber[line].ok) {
        c.chamber_tau_us = static_cast<uint32_t>(std::max(1.0, u.chamber[line].tau_s * 1e6));
        c.overdrive_pa = ph::kShapingOverdrivePa;
        c.slew_pa_per_s = 0;
      }
      board_.SendConfig(c);
      board_.Run(5);
      if (board.lines[line].chamber_tau_us != c.chamber_tau_us ||
          board.lines[line].correction_count != c.correction_count) {
        std::fprintf(stderr, "scene bench: line %u's calibration was not applied\n", line);
        return false;
      }
    }
    return true;
  }
  /// A finger's true output in its unit: deformation (mm) or stiffness (N/mm).
  double True(const ps::PlantTruth& t, size_t f) const {
    return jamming_ ? t.fingers[f].stiffness_n_per_mm : t.fingers[f].deformation_mm;
  }
  double Target0(double x) const { return scene_.Render({0, x, kY, 1})[0].mapped.target / 1000.0; }
  void SendTargets(double x) {
    pp::SetFingerTargets t{};
    t.session = testing::InProcessBoard::kSession;
    t.generation = board_.next_generation();
    const auto renders = scene_.Render({0, x, kY, 1});
    const auto requests = scene_.Requests(renders);
    for (size_t f = 0; f < renders.size(); ++f) {
      t.entries[t.entry_count++] = {requests[f].finger,
                                    jamming_ ? pp::OutputUnit::kStiffnessMilliNewtonPerMm
                                             : pp::OutputUnit::kDeformationMicrometre,
                                    renders[f].mapped.target};
    }
    board_.Send(t, false);
  }

  const ph::SceneRenderer& scene_;
  bool jamming_;
  testing::InProcessBoard board_;
  bool ok_ = true;
};

}  // namespace palpa::bench
