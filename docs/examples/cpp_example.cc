// palpa from C++: open a simulated board, set fingers in people's terms and see what each became,
// follow their outputs from telemetry, E-stop. CMake: find_package(palpa) and palpa::palpa.
#include <palpa/host/device.h>
#include <palpa/host/scene.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

namespace ph = palpa::host;

int main(int argc, char** argv) {
  auto opened = ph::Device::Open("sim:thesis-5finger", {});
  if (!opened.ok()) {  // a Result: the value, or the status and its message
    std::fprintf(stderr, "open: %s\n", opened.message.c_str());
    return 1;
  }
  ph::Device& board = *opened.value;
  const auto info = board.info();

  // Fingers from 0, as on the wire: a level, a deformation, a stiffness.
  std::vector<ph::Applied> applied;
  const ph::Outcome set = board.Set({{0, {ph::TargetKind::kLevel, 2}},
                                     {1, {ph::TargetKind::kDeformationMm, 0.5}},
                                     {3, {ph::TargetKind::kStiffnessNPerMm, 1.1}}},
                                    true, &applied);
  if (!set.ok()) {
    std::fprintf(stderr, "set: %s\n", set.message.c_str());
    return 1;
  }
  for (const ph::Applied& a : applied)
    std::printf("finger %u: target %.3f %s (%s)\n", a.finger, a.target, a.unit, a.map.c_str());

  // Telemetry arrives on the library's thread; each finger's output through its curve.
  std::vector<ph::FingerCurves> curves;
  for (uint8_t f = 0; f < info.finger_count; ++f) curves.push_back(board.curves(f));
  std::mutex mutex;
  std::vector<double> outputs;
  const int id = board.Subscribe([&](const ph::TelemetryFrame& frame) {
    const auto& t = frame.telemetry;
    if (t.line_count != info.line_count) return;
    std::lock_guard<std::mutex> lock(mutex);
    outputs =
        ph::EstimateFingerOutputs(info, curves, &t.samples[(t.tick_count - 1) * t.line_count]);
  });
  std::this_thread::sleep_for(std::chrono::seconds(1));  // re-homing (~350 ms), then the move
  board.Unsubscribe(id);
  std::printf("outputs:");
  for (size_t f = 0; f < outputs.size(); ++f)
    std::printf(" %.3f %s", outputs[f], ph::OutputUnitName(info.fingers[f].kind));
  std::printf("\n");

  // A scene (docs/scenes.md): each sample rendered and sent to every finger in one frame,
  // without waiting.
  // The scene file: the first argument, or the example's beside this source.
  const std::string source = __FILE__;
  const auto spec =
      ph::LoadScene(argc > 1 ? std::string(argv[1])
                             : source.substr(0, source.rfind('/') + 1) + "scene_three_cube.json");
  auto scene = spec.ok() ? ph::Scene::Open(spec.value, board)
                         : ph::Result<std::unique_ptr<ph::Scene>>(spec.outcome());
  if (!scene.ok()) {
    std::fprintf(stderr, "scene: %s\n", scene.message.c_str());
    return 1;
  }
  for (int step = 0; step <= 30; ++step) {
    const auto fed = scene.value->Feed({step * 0.02, 45.0 + step, 12, 1.0});
    if (!fed.ok()) return 1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  board.EStop();
  return outputs.size() == info.finger_count && outputs[0] > 0.9 ? 0 : 2;
}
