// A scene on palpa-sim: fed without waiting, every finger's target goes in one frame (one
// generation of the targets stream) and the board changes all of them on the same tick; a scene
// naming a finger the board lacks is refused.
#include <algorithm>
#include <chrono>
#include <map>
#include <mutex>
#include <thread>

#include "palpa/host/scene.h"

#include "CppUTest/TestHarness.h"
#include "scene_examples.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

std::unique_ptr<ph::Device> OpenSim() {
  ph::DeviceOptions options;
  options.use_calibrations = false;
  auto opened = ph::Device::Open("sim:thesis-pneumatic-3", options);
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  return std::move(opened.value);
}

/// Each line's setpoint at every tick the board reported, by board time (µs).
struct Ticks {
  std::mutex mutex;
  std::map<uint64_t, std::vector<int32_t>> setpoints;
  void Add(const ph::TelemetryFrame& f) {
    const pp::Telemetry& t = f.telemetry;
    std::lock_guard<std::mutex> lock(mutex);
    for (uint8_t i = 0; i < t.tick_count; ++i) {
      std::vector<int32_t>& row = setpoints[t.first_sample_us + uint64_t{i} * t.sample_interval_us];
      row.clear();
      for (uint8_t l = 0; l < t.line_count; ++l)
        row.push_back(t.samples[i * t.line_count + l].setpoint_pa);
    }
  }
  /// The first tick after `after` at which line `line` reads 0 having read more before; 0: none.
  uint64_t FirstZero(size_t line, uint64_t after) {
    std::lock_guard<std::mutex> lock(mutex);
    bool was_up = false;
    for (const auto& [us, row] : setpoints) {
      if (us < after || line >= row.size()) continue;
      if (row[line] > 0) was_up = true;
      if (was_up && row[line] == 0) return us;
    }
    return 0;
  }
  uint64_t Last() {
    std::lock_guard<std::mutex> lock(mutex);
    return setpoints.empty() ? 0 : setpoints.rbegin()->first;
  }
};

}  // namespace

TEST_GROUP(SceneDevice){};

TEST(SceneDevice, EveryFingerChangesOnTheSameTick) {
  auto device = OpenSim();
  auto spec = ph::LoadScene(palpa::testing::kThreeCubeScene);
  CHECK_TEXT(spec.ok(), spec.message.c_str());
  spec.value.rule.pneumatic = ph::PneumaticMapping::kDeformation;
  spec.value.rule.value_lo = 0;  // the block itself renders mid-range, so every finger is up
  spec.value.rule.value_hi = 40;
  auto scene = ph::Scene::Open(spec.value, *device);
  CHECK_TEXT(scene.ok(), scene.message.c_str());
  Ticks ticks;
  const int id = device->Subscribe([&](const ph::TelemetryFrame& f) { ticks.Add(f); });
  // All three fingers on the block: each at 14.7 / 40 of its curve.
  auto fed = scene.value->Feed({0, 10, 5, 1});
  CHECK_TEXT(fed.ok(), fed.message.c_str());
  for (const ph::FingerRender& r : fed.value) CHECK(r.mapped.target > 1000);
  // Wait until every finger's line is up (after the re-homing dwell), whatever the load.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  auto all_up = [&] {
    std::lock_guard<std::mutex> lock(ticks.mutex);
    if (ticks.setpoints.empty()) return false;
    const auto& row = ticks.setpoints.rbegin()->second;
    return row.size() >= 3 &&
           std::all_of(row.begin(), row.begin() + 3, [](int32_t p) { return p > 0; });
  };
  while (!all_up() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  CHECK_TEXT(all_up(), "the fingers never rose");
  const uint64_t before = ticks.Last();
  // Lifted: every finger released by one frame — one new generation of the targets stream, not
  // one per finger.
  const uint32_t generation = device->link().targets_generation();
  fed = scene.value->Feed({0.1, 10, 5, 0});
  CHECK_TEXT(fed.ok(), fed.message.c_str());
  CHECK_EQUAL(generation + 1, device->link().targets_generation());
  uint64_t first[3] = {0, 0, 0};
  while (std::chrono::steady_clock::now() < deadline) {
    for (size_t f = 0; f < 3; ++f)
      first[f] = ticks.FirstZero(device->info().fingers[f].line_a, before);
    if (first[0] && first[1] && first[2]) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  device->Unsubscribe(id);
  CHECK_TEXT(first[0] != 0, "finger 0 was never released");
  CHECK_EQUAL(first[0], first[1]);
  CHECK_EQUAL(first[0], first[2]);
}

TEST(SceneDevice, AFingerTheBoardLacksIsRefused) {
  auto device = OpenSim();
  auto spec = ph::LoadScene(palpa::testing::kThreeCubeScene).value;
  spec.board_fingers = {0, 1, 5};
  const auto scene = ph::Scene::Open(spec, *device);
  CHECK(!scene.ok());
  STRCMP_EQUAL("fingers[2]: finger 5 does not exist on this board (3 fingers)",
               scene.message.c_str());
}
