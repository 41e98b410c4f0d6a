// Scenes: input sample → DAC write latency through a Scene, on one clock. palpa-sim runs in real
// time (--speed 1) and stamps, on CLOCK_MONOTONIC, when each generation of finger targets is
// dispatched and when the DAC is first written with it; the host stamps each sample on the same
// clock just before Scene::Feed renders it and sends every finger's target in one frame.
// Samples come at a pen tablet's 100 Hz with a random phase against the board's tick, the input
// sweeping the tissue at 30 mm/s. The board is a held-out unit whose fingers are calibrated as
// palpa calibrate does (on an in-process rig of the same unit, as the scene bench) and applied
// as the host applies the files: its lines' steps shaped, the chamber estimated from the outlet.
//   palpa_scene_latency_bench SCENE.json [SAMPLES]
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <thread>

#include "generation_stamps.h"
#include "palpa/host/device.h"
#include "palpa/host/field_text.h"
#include "palpa/host/scene.h"
#include "scene_pass.h"
#include "sim_process.h"

namespace pb = palpa::bench;
namespace ph = palpa::host;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: palpa_scene_latency_bench SCENE.json [SAMPLES]\n");
    return 2;
  }
  const int samples = argc > 2 ? std::atoi(argv[2]) : 2000;
  const auto spec = ph::LoadScene(argv[1]);
  if (!spec.ok()) return std::fprintf(stderr, "%s\n", spec.message.c_str()), 1;
  const std::string stamps = "/tmp/palpa-scene-latency-" + std::to_string(getpid()) + ".txt";
  constexpr const char* kConfig = "thesis-pneumatic-3";
  const std::string unit = std::to_string(pb::kUnit);
  palpa::testing::SimProcess sim;
  if (!sim.Start({"--config", kConfig, "--unit", unit, "--seed", unit, "--speed", "1", "--listen",
                  "tcp:127.0.0.1:0", "--stamp", "file:" + stamps})) {
    std::fprintf(stderr, "palpa-sim did not start: %s\n", sim.output().c_str());
    return 1;
  }
  ph::DeviceOptions options;
  options.use_calibrations = false;  // the files made here, not what this machine holds
  auto device = ph::Device::Open(sim.address(), options);
  if (!device.ok()) return std::fprintf(stderr, "%s\n", device.message.c_str()), 1;
  for (const uint8_t f : spec.value.board_fingers) {
    const ph::CalibrationFile* made = pb::ScenePass::FingerCalibrationFor(kConfig, f);
    if (made == nullptr) return 1;
    ph::CalibrationFile file = *made;
    const auto finger = device.value->ReadFinger(f);
    if (!finger.ok()) return std::fprintf(stderr, "%s\n", finger.message.c_str()), 1;
    file.actuator_serial = ph::FieldText(finger.value.actuator_serial);  // the same unit's
    const ph::Outcome applied = device.value->ApplyCalibration(f, file);
    if (!applied.ok())
      return std::fprintf(stderr, "finger %u: %s\n", f, applied.message.c_str()), 1;
    // What the board now runs: a shaped line estimates its chamber from the outlet.
    const auto line = device.value->ReadLine(finger.value.line_a);
    if (!line.ok()) return std::fprintf(stderr, "%s\n", line.message.c_str()), 1;
    if (line.value.chamber_tau_us == 0 || line.value.overdrive_pa == 0)
      return std::fprintf(stderr, "finger %u: its line is not shaped\n", f), 1;
    std::printf("finger %u: line %u shaped, the tube's lag %.1f ms\n", f, finger.value.line_a + 1,
                line.value.chamber_tau_us * 1e-3);
  }
  auto scene = ph::Scene::Open(spec.value, *device.value);
  if (!scene.ok()) return std::fprintf(stderr, "%s\n", scene.message.c_str()), 1;
  // The first sample switches the fingers to target mode (a command round trip): not measured.
  if (auto first = scene.value->Feed({0, 20, 15, 1}); !first.ok())
    return std::fprintf(stderr, "%s\n", first.message.c_str()), 1;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));

  std::map<uint32_t, int64_t> fed;
  std::mt19937 rng(1);
  double x = 20, dx = 0.3;  // 30 mm/s at 100 Hz, back and forth over the cubes
  for (int i = 0; i < samples; ++i) {
    std::this_thread::sleep_for(std::chrono::microseconds(9000 + rng() % 2000));
    if (x + dx > 100 || x + dx < 20) dx = -dx;
    x += dx;
    const int64_t t = pb::MonotonicNs();
    const auto sent = scene.value->Feed({0.01 * i, x, 15, 1});
    if (!sent.ok()) return std::fprintf(stderr, "sample %d: %s\n", i, sent.message.c_str()), 1;
    fed[device.value->link().targets_generation()] = t;
  }
  scene.value.reset();
  device.value.reset();
  sim.Stop();
  const pb::LatencySplit l = pb::Match(fed, pb::ReadGenerationStamps(stamps, "targets"));
  std::remove(stamps.c_str());
  if (l.total.empty()) return std::fprintf(stderr, "no stamps matched\n"), 1;
  std::printf(
      "== input sample -> DAC write through the scene %s, palpa-sim --speed 1 over TCP "
      "(loopback), unit %u calibrated, %zu of %d samples stamped ==\n",
      spec.value.name.c_str(), pb::kUnit, l.total.size(), samples);
  pb::PrintLatency("sample -> DAC write", l.total);
  pb::PrintLatency("  of which render + link", l.link);
  pb::PrintLatency("  of which tick quantisation", l.tick);
  return 0;
}
