// A scene bound to a board: fingers from the device, each sample's targets sent in one frame.
#include "palpa/host/scene.h"

namespace palpa::host {

Result<std::unique_ptr<Scene>> Scene::Make(TissueMap tissue, FingerLayout layout, RenderRule rule,
                                           const std::vector<uint8_t>& board_fingers,
                                           Device& device) {
  const pp::HelloReply board = device.info();
  std::vector<RenderFinger> fingers;
  for (size_t k = 0; k < board_fingers.size(); ++k) {
    const uint8_t f = board_fingers[k];
    if (f >= board.finger_count) {
      return {Status::kNotFound, "fingers[" + std::to_string(k) + "]: " + device.FingerName(f) +
                                     " does not exist on this board (" +
                                     std::to_string(board.finger_count) + " fingers)"};
    }
    fingers.push_back({f, board.fingers[f], device.curves(f)});
  }
  auto renderer = SceneRenderer::Make(std::move(tissue), std::move(layout), rule,
                                      std::move(fingers), device.levels());
  if (!renderer.ok()) return renderer.outcome();
  return std::unique_ptr<Scene>(new Scene(std::move(renderer.value), device));
}

Result<std::unique_ptr<Scene>> Scene::Open(const SceneSpec& spec, Device& device) {
  auto tissue = LoadSceneTissue(spec);
  if (!tissue.ok()) return tissue.outcome();
  return Make(std::move(tissue.value), MakeLayout(spec.layout), spec.rule, spec.board_fingers,
              device);
}

Result<std::vector<FingerRender>> Scene::Send(std::vector<FingerRender> renders) {
  const Outcome sent = device_.Set(renderer_.Requests(renders), /*wait=*/false);
  if (!sent.ok()) return sent;
  return renders;
}

Result<std::vector<FingerRender>> Scene::Feed(const SceneInput& input) {
  return Send(renderer_.Render(predictor_ ? predictor_->Next(input) : input));
}

Result<std::vector<FingerRender>> Scene::FeedValues(const std::vector<double>* values, double lo,
                                                    double hi) {
  return Send(renderer_.RenderValues(values, lo, hi));
}

Result<double> Scene::DisplayDelay() {
  double sum = 0;
  for (size_t k = 0; k < renderer_.fingers().size(); ++k) {
    const RenderFinger& f = renderer_.fingers()[k];
    const bool jamming = f.summary.kind == protocol::FingerKind::kJamming;
    const uint8_t line = jamming ? f.summary.line_b : f.summary.line_a;
    const auto config = device_.ReadLine(line);
    if (!config.ok()) return config.outcome();
    const auto delay = host::DisplayDelay(config.value, SceneStepPa(renderer_, k));
    if (!delay.ok()) {
      return {delay.status, device_.FingerName(f.board_finger) + ": " + delay.message};
    }
    sum += delay.value;
  }
  return sum / static_cast<double>(renderer_.fingers().size());
}

Outcome Scene::Predict(std::optional<PredictorOptions> options) {
  if (!options) {
    predictor_.reset();
    return {};
  }
  if (Outcome ok = CheckPredictor(*options); !ok.ok()) return ok;
  predictor_.emplace(*options);
  const TissueMap& t = renderer_.tissue();
  predictor_->SetExtent(t.extent_x_mm(), t.extent_y_mm());
  return {};
}

}  // namespace palpa::host
