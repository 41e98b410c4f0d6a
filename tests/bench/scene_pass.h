// One pass of a scene over the simulated board in virtual time (plant level 3, a held-out unit):
// each input sample rendered and sent as one SetFingerTargets, every board tick each finger's true
// output scored against the rule's target at its current position, and the edge lag at cube B.
// The board's fingers on their nominal curves, or each calibrated on its rig first by palpa
// calibrate's protocol and the file applied as the host applies it (curve, compensator, each
// line's static correction and chamber model: steps shaped).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "in_process_board.h"
#include "palpa/calibration/calibration_protocol.h"
#include "palpa/host/board_curves.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/scene_predict.h"
#include "palpa/host/scene_render.h"
#include "sim_rig.h"

namespace palpa::bench {

namespace ps = palpa::sim;
namespace pp = palpa::protocol;
namespace ph = palpa::host;

constexpr int kInputEveryMs = 10;
constexpr double kStartX = 20, kEndX = 100;
/// The passes' lines: the cubes' mid-line, and 15 mm below it, where the triangle's third finger
/// (15 mm above the input) runs along the mid-line and crosses the cubes.
constexpr double kMidLineY = 15, kSecondLineY = 0;

/// One finger's score over a pass.
struct FingerScore {
  std::vector<double> errors;         ///< |true − target| / range, every tick
  double edge_lag_mm = NAN;           ///< NAN: the output never crossed half of the change over B
  bool meets_edge = false;            ///< the finger's path crosses cube B's near face at all
  double edge_speed_mm_s = NAN;       ///< the finger's speed where the rule's target crossed at B
  std::vector<double> place, output;  ///< the finger's x and true output, every tick
};
using PassResult = std::vector<FingerScore>;

constexpr uint32_t kUnit = 12;  // a held-out unit (actuators, regulators, sensors): not nominal

class ScenePass {
 public:
  /// `board_fingers` are the scene's, calibrated when `calibrated`.
  ScenePass(const ph::SceneRenderer& scene, bool jamming, bool calibrated,
            const std::vector<uint8_t>& board_fingers)
      : scene_(&scene),
        jamming_(jamming),
        config_(jamming ? "thesis-jamming-2" : "thesis-pneumatic-3"),
        board_(testing::PlantBoardOptions(jamming ? "thesis-jamming-2" : "thesis-pneumatic-3",
                                          kUnit, kUnit, {})) {
    if (calibrated) ok_ = Calibrate(board_fingers) && RenderThroughCalibrations(board_fingers);
  }
  /// False when the board refused a calibrated line's configuration (said on stderr).
  bool ok() const { return ok_; }
  /// The renderer the pass uses (through the calibrations, when calibrated).
  const ph::SceneRenderer& scene() const { return *scene_; }

  /// From now on each input sample is replaced by its prediction over the display delay of the
  /// scene's fingers, from their lines' calibrated configuration (as Scene::DisplayDelay reads
  /// it from a board). False (said on stderr) when a line has no chamber model.
  bool Predict() {
    double sum = 0;
    for (size_t k = 0; k < scene_->fingers().size(); ++k) {
      const pp::FingerSummary& f = scene_->fingers()[k].summary;
      const uint8_t line = jamming_ ? f.line_b : f.line_a;  // the line that sets its output
      const auto delay = ph::DisplayDelay(board_.config().lines[line], ph::SceneStepPa(*scene_, k));
      if (!delay.ok()) {
        std::fprintf(stderr, "scene bench: %s\n", delay.message.c_str());
        return false;
      }
      sum += delay.value;
    }
    ph::PredictorOptions o;
    o.horizon_s = sum / static_cast<double>(scene_->fingers().size());
    predictor_.emplace(o);
    predictor_->SetExtent(scene_->tissue().extent_x_mm(), scene_->tissue().extent_y_mm());
    return true;
  }
  /// The prediction horizon (s; 0: no prediction).
  double horizon_s() const { return predictor_ ? predictor_->options().horizon_s : 0; }
  /// The scene's fingers whose line's shaped steps fell back to unshaped, slew-limited ones (the
  /// outlet ran ahead of the model) by the end of the last pass.
  size_t FellBack() const {
    size_t n = 0;
    for (const ph::RenderFinger& f : scene_->fingers()) {
      const uint8_t line = jamming_ ? f.summary.line_b : f.summary.line_a;
      n += board_.sim().board().line_state(line).shaping_fell_back ? 1 : 0;
    }
    return n;
  }
  /// Samples predicted over the last pass, of all it sent.
  size_t predicted() const { return predicted_; }
  size_t samples() const { return samples_; }
  /// The calibration file of `finger` of unit kUnit behind `config`, run once per finger
  /// (the study bench applies the same files to a palpa-sim of the same unit).
  static const ph::CalibrationFile* FingerCalibrationFor(const std::string& config,
                                                         uint8_t finger) {
    static std::map<std::pair<std::string, uint8_t>, ph::CalibrationFile> known;
    const auto found = known.find({config, finger});
    if (found != known.end()) return &found->second;
    testing::SimRig sim({config, finger, kUnit, kUnit});
    calibration::Rig rig = sim.rig();
    calibration::Journal journal;
    calibration::CalibrationRun run;
    const std::string serial = "U" + std::to_string(kUnit) + "-F" + std::to_string(finger);
    const calibration::RunInfo info{serial, kUnit, "2026-11-26T00:00:00Z", "sim", serial + ".csv"};
    const calibration::RigStatus status = calibration::RunCalibration(
        rig, finger, calibration::ProtocolOptions{}, info, journal, nullptr, &run);
    if (!status.ok()) {
      std::fprintf(stderr, "calibrating finger %u failed: %s\n", finger, status.message.c_str());
      return nullptr;
    }
    std::fprintf(stderr, "%s finger %u calibrated in %.0f s of rig time (%s)\n", config.c_str(),
                 finger, sim.Now(), ph::CompensatorLabel(run.file).c_str());
    return &(known[{config, finger}] = run.file);
  }
  /// A hand's tremor (or a pad's noise): each input sample's x and y moved by a normal draw of
  /// this RMS (mm), the same draws every run.
  void SetTremor(double rms_mm) { tremor_mm_ = rms_mm; }

  /// A path along y = `y`: the input's x at each millisecond of the pass (after settling at the
  /// first).
  PassResult Pass(const std::vector<double>& path, double y, double range_mm) {
    y_ = y;
    const size_t n = scene_->layout().fingers.size();
    PassResult r(n);
    // Settle at the start (the first target re-homes the fingers), then the pass.
    const int settle_ms = 1500;
    const int pass_ms = static_cast<int>(path.size()) - 1;
    const double edge = 54;  // cube B's near face
    // Each finger's half-change at B's face: the rule's targets 3 mm either side of it where the
    // finger itself is (its offset from the input), and where each of them crossed it.
    std::vector<double> half(n), rule_cross(n, NAN), previous_true(n, 0);
    for (size_t f = 0; f < n; ++f) {
      const double dx = scene_->layout().fingers[f].dx_mm;
      const double before = Target(f, edge - 3 - dx), on = Target(f, edge + 3 - dx);
      half[f] = (before + on) / 2;
      r[f].meets_edge = on - before > 0.05 * range_mm;  // a change worth timing
    }
    std::mt19937 rng(7);
    std::normal_distribution<double> tremor(0, 1);
    predicted_ = samples_ = 0;
    for (int ms = -settle_ms; ms <= pass_ms; ++ms) {
      const double x = path[static_cast<size_t>(std::max(0, ms))];
      if (ms % kInputEveryMs == 0) {
        ph::SceneInput in{(ms + settle_ms) * 1e-3, x, y_, 1};
        if (tremor_mm_ > 0 && ms >= 0) {
          in.x_mm += tremor_mm_ * tremor(rng);
          in.y_mm += tremor_mm_ * tremor(rng);
        }
        if (predictor_) {
          in = predictor_->Next(in);
          predicted_ += ms >= 0 && predictor_->last() == ph::Prediction::kPredicted;
        }
        samples_ += ms >= 0;
        SendTargets(in.x_mm, in.y_mm);
      }
      board_.Run(1);
      if (ms < 0) continue;
      const auto truth = board_.sim().plant().Truth();
      const auto now = scene_->Render({0, x, y_, 1});
      for (size_t f = 0; f < n; ++f) {
        const double target = now[f].mapped.target / 1000.0;
        const double true_f = True(truth, f);
        FingerScore& s = r[f];
        s.errors.push_back(std::fabs(true_f - target) / range_mm);
        const double at = x + scene_->layout().fingers[f].dx_mm;
        s.place.push_back(at);
        s.output.push_back(true_f);
        if (!s.meets_edge) continue;
        if (std::isnan(rule_cross[f]) && target >= half[f]) {
          rule_cross[f] = at;
          // The hand-like passes vary their speed: this is the speed the lag is made at.
          s.edge_speed_mm_s = 1000 * std::fabs(x - path[static_cast<size_t>(std::max(0, ms - 1))]);
        }
        if (std::isnan(s.edge_lag_mm) && !std::isnan(rule_cross[f]) && previous_true[f] < half[f] &&
            true_f >= half[f])
          s.edge_lag_mm = at - rule_cross[f];
        previous_true[f] = true_f;
      }
    }
    return r;
  }

 private:
  /// Each finger calibrated on its rig as palpa calibrate does (the whole protocol: zero, the
  /// regulator's correction, the chamber's step, the deformation or stiffness curve and its
  /// compensator), then applied as the host applies the file: the finger's record and its lines'.
  bool Calibrate(const std::vector<uint8_t>& fingers) {
    const core::BoardConfig& board = board_.config();
    for (uint8_t finger : fingers) {
      const ph::CalibrationFile* file = FingerCalibrationFor(config_, finger);
      if (file == nullptr) return false;
      const auto calibrated = ph::CalibratedFinger(board.fingers[finger], *file);
      if (!calibrated.ok()) {
        std::fprintf(stderr, "scene bench: finger %u: %s\n", finger, calibrated.message.c_str());
        return false;
      }
      const pp::ConfigureFinger& f = calibrated.value;
      board_.SendConfig(f);
      board_.Run(5);
      if (board.fingers[finger].inverse_count != f.inverse_count ||
          board.fingers[finger].param_count != f.param_count) {
        std::fprintf(stderr, "scene bench: finger %u's calibration was not applied\n", finger);
        return false;
      }
      for (const uint8_t line : {f.line_a, f.line_b}) {
        if (line == pp::kNoLine) continue;
        pp::ConfigureLine c = board.lines[line];
        const auto changed = ph::CalibratedLine(*file, line, c);
        if (!changed.ok()) {
          std::fprintf(stderr, "scene bench: %s\n", changed.message.c_str());
          return false;
        }
        if (!changed.value) continue;
        board_.SendConfig(c);
        board_.Run(5);
        if (board.lines[line].chamber_tau_us != c.chamber_tau_us ||
            board.lines[line].correction_count != c.correction_count) {
          std::fprintf(stderr, "scene bench: line %u's calibration was not applied\n", line);
          return false;
        }
      }
    }
    return true;
  }
  /// As a Scene on a Device renders: through the curves each finger's calibration gave it (the
  /// board's calibrated inverse), so the rule's targets are this unit's, not the nominal curve's.
  bool RenderThroughCalibrations(const std::vector<uint8_t>& fingers) {
    const core::BoardConfig& board = board_.config();
    std::vector<ph::RenderFinger> calibrated;
    for (uint8_t f : fingers) {
      const pp::ConfigureFinger& c = board.fingers[f];
      calibrated.push_back({f,
                            {c.kind, pp::FingerMode::kTarget, c.line_a, c.line_b},
                            ph::CurvesFromBoard(c, "calibration applied")});
    }
    auto made =
        ph::SceneRenderer::Make(scene_->tissue(), scene_->layout(), scene_->rule(), calibrated);
    if (!made.ok()) {
      std::fprintf(stderr, "scene bench: %s\n", made.message.c_str());
      return false;
    }
    calibrated_scene_ = std::make_unique<ph::SceneRenderer>(std::move(made.value));
    scene_ = calibrated_scene_.get();
    return true;
  }
  /// A finger's true output in its unit: deformation (mm) or stiffness (N/mm).
  double True(const ps::PlantTruth& t, size_t f) const {
    return jamming_ ? t.fingers[f].stiffness_n_per_mm : t.fingers[f].deformation_mm;
  }
  double Target(size_t f, double x) const {
    return scene_->Render({0, x, y_, 1})[f].mapped.target / 1000.0;
  }
  void SendTargets(double x, double y) {
    pp::SetFingerTargets t{};
    t.session = testing::InProcessBoard::kSession;
    t.generation = board_.next_generation();
    const auto renders = scene_->Render({0, x, y, 1});
    const auto requests = scene_->Requests(renders);
    for (size_t f = 0; f < renders.size(); ++f) {
      t.entries[t.entry_count++] = {requests[f].finger,
                                    jamming_ ? pp::OutputUnit::kStiffnessMilliNewtonPerMm
                                             : pp::OutputUnit::kDeformationMicrometre,
                                    renders[f].mapped.target};
    }
    board_.Send(t, false);
  }

  const ph::SceneRenderer* scene_;  ///< the scene's own, or rendering through the calibrations
  std::unique_ptr<ph::SceneRenderer> calibrated_scene_;
  bool jamming_;
  std::string config_;
  testing::InProcessBoard board_;
  bool ok_ = true;
  double y_ = kMidLineY;  ///< the pass's line
  std::optional<ph::MotionPredictor> predictor_;
  double tremor_mm_ = 0;
  size_t predicted_ = 0, samples_ = 0;
};

}  // namespace palpa::bench
