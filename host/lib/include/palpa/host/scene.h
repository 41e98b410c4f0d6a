// A scene bound to a board: each input sample rendered and every finger's target sent in one
// stream frame without waiting (latest-wins), so an application can feed samples at its own rate.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/host/outcome.h"
#include "palpa/host/scene_file.h"
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

  const SceneRenderer& renderer() const { return renderer_; }

 private:
  Scene(SceneRenderer renderer, Device& device) : renderer_(std::move(renderer)), device_(device) {}
  SceneRenderer renderer_;
  Device& device_;
};

}  // namespace palpa::host
