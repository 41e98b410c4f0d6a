// A scene bound to a board: each input sample rendered and every finger's target sent in one
// stream frame without waiting (latest-wins), so an application can feed samples at its own rate.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/host/outcome.h"
#include "palpa/host/scene_file.h"
#include "palpa/host/scene_predict.h"
#include "palpa/host/scene_render.h"

namespace palpa::host {

class Scene {
 public:
  /// A scene file's scene on `device`: its tissue loaded, each place's board finger checked
  /// against the board, the finger's kind and curves (calibrated where the device found a
  /// calibration) taken from the device. `device` must outlive the scene.
  static Result<std::unique_ptr<Scene>> Open(const SceneSpec& spec, Device& device);
  /// The same from parts already made.
  static Result<std::unique_ptr<Scene>> Make(TissueMap tissue, FingerLayout layout, RenderRule rule,
                                             const std::vector<uint8_t>& board_fingers,
                                             Device& device);

  /// Renders one input sample and sends every finger's target together (one SetFingerTargets
  /// frame, so the board applies them on one tick) without waiting for the board: a later sample
  /// replaces one not yet applied. The first call, or one after a finger was put in another mode,
  /// switches the fingers to target mode first (a command round trip). On success, the renders
  /// say what each finger touched and was asked.
  Result<std::vector<FingerRender>> Feed(const SceneInput& input);

  /// Values per finger already known (a tactile array's group means), rendered over lo … hi
  /// (SceneRenderer::RenderValues) and sent as Feed sends; nullptr releases every finger.
  Result<std::vector<FingerRender>> FeedValues(const std::vector<double>* values, double lo,
                                               double hi);

  /// The display's delay for this scene's fingers (scene_predict.h DisplayDelay): each finger's
  /// driving line — a pneumatic finger's pressure line, a jamming finger's vacuum line — read
  /// from the board, as its calibration configured it; the mean over the fingers. Unavailable,
  /// naming the line, when one has no chamber model.
  Result<double> DisplayDelay();
  /// From now on each Feed renders where the input is predicted to be (MotionPredictor, held on
  /// the tissue); nullopt renders the input as it is. Refused for bad options.
  Outcome Predict(std::optional<PredictorOptions> options);
  /// The predictor in use (nullptr: none): what the last Feed predicted, and why not.
  const MotionPredictor* predictor() const { return predictor_ ? &*predictor_ : nullptr; }

  const SceneRenderer& renderer() const { return renderer_; }

 private:
  Scene(SceneRenderer renderer, Device& device) : renderer_(std::move(renderer)), device_(device) {}
  Result<std::vector<FingerRender>> Send(std::vector<FingerRender> renders);
  SceneRenderer renderer_;
  Device& device_;
  std::optional<MotionPredictor> predictor_;
};

}  // namespace palpa::host
