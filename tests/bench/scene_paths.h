// The scene benchmarks' passes across the three-cube phantom — straight at a constant speed, and
// hand-like: speed varying, stops and a reversal over cube B; a position per millisecond — and
// their scenes, from the scene file a benchmark is given: its pneumatic fingers (the example's
// triangle) and the jamming pair; and the target range.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>
#include <vector>

#include "palpa/host/scene_file.h"
#include "scene_pass.h"

namespace palpa::bench {

/// A straight pass at a constant speed, a position per millisecond.
inline std::vector<double> Straight(double speed_mm_s) {
  std::vector<double> path;
  for (double x = kStartX; x <= kEndX; x += speed_mm_s / 1000) path.push_back(x);
  return path;
}

/// A hand-like pass: speed varying ±50 % about `speed` (a 2 s cycle), forward to 80 mm, a 0.5 s
/// stop, back to 60 mm (over cube B again), another stop, then on to the end.
inline std::vector<double> HandLike(double speed) {
  std::vector<double> path;
  double x = kStartX, t = 0;
  auto go = [&](double to) {
    const double dir = to > x ? 1 : -1;
    while (dir * (to - x) > 0) {
      x += dir * speed * (1 + 0.5 * std::sin(2 * M_PI * t / 2)) / 1000;
      t += 0.001;
      path.push_back(x);
    }
  };
  auto stop = [&] {
    for (int ms = 0; ms < 500; ++ms) path.push_back(x);
  };
  go(80);
  stop();
  go(60);
  stop();
  go(kEndX);
  return path;
}

/// The scene's target range: from the softest to the stiffest target the rule gives a finger on
/// the tissue along the cubes' mid-line.
inline std::pair<double, double> TargetRange(const ph::SceneRenderer& scene) {
  double lo = 1e9, hi = -1e9;
  for (double x = 0; x <= 120; x += 0.25) {
    for (const auto& r : scene.Render({0, x, kMidLineY, 1})) {
      if (!r.touching) continue;  // off the tissue: released, not part of the range
      lo = std::min(lo, r.mapped.target / 1000.0);
      hi = std::max(hi, r.mapped.target / 1000.0);
    }
  }
  return {lo, hi};
}

/// The scene file's scene on the pneumatic fingers of its board fingers (nominal curves).
inline ph::Result<ph::SceneRenderer> PneumaticScene(const ph::SceneSpec& spec,
                                                    const ph::TissueMap& tissue) {
  std::vector<ph::RenderFinger> fingers;
  for (uint8_t f : spec.board_fingers)
    fingers.push_back(
        {f, {pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, f, pp::kNoLine}, {}});
  return ph::SceneRenderer::Make(tissue, ph::MakeLayout(spec.layout), spec.rule, fingers);
}

/// The jamming pair on the same tissue, 20 mm apart, a 4 mm disc, N/mm over each finger's
/// nominal curve: fingers 0 and 1, bias lines 0 and 1, vacuum lines 2 and 3.
inline ph::Result<ph::SceneRenderer> JammingPairScene(const ph::TissueMap& tissue) {
  std::vector<ph::RenderFinger> pair;
  for (uint8_t f = 0; f < 2; ++f) {
    pair.push_back(
        {f,
         {pp::FingerKind::kJamming, pp::FingerMode::kTarget, f, static_cast<uint8_t>(f + 2)},
         {}});
  }
  return ph::SceneRenderer::Make(tissue, ph::JammingPairLayout(20, 4), {}, pair);
}

/// A scene benchmark's scenes, from the scene file it is given: the file's scene on its pneumatic
/// fingers (nominal curves), and the jamming pair on the same tissue.
struct BenchScenes {
  ph::SceneSpec spec;
  ph::SceneRenderer pneumatic, jamming;
};

/// `program SCENE.json`'s scenes; nullopt, said on stderr, with the exit status in `status` (2: the
/// command line, 1: a scene that cannot be made).
inline std::optional<BenchScenes> LoadBenchScenes(int argc, char** argv, const char* program,
                                                  int* status) {
  *status = 1;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SCENE.json\n", program);
    *status = 2;
    return std::nullopt;
  }
  BenchScenes out;
  const auto spec = ph::LoadScene(argv[1]);
  if (!spec.ok()) return std::fprintf(stderr, "%s\n", spec.message.c_str()), std::nullopt;
  const auto tissue = ph::LoadSceneTissue(spec.value);
  if (!tissue.ok()) return std::fprintf(stderr, "%s\n", tissue.message.c_str()), std::nullopt;
  auto scene = PneumaticScene(spec.value, tissue.value);
  if (!scene.ok()) return std::fprintf(stderr, "%s\n", scene.message.c_str()), std::nullopt;
  auto jamming = JammingPairScene(tissue.value);
  if (!jamming.ok()) return std::fprintf(stderr, "%s\n", jamming.message.c_str()), std::nullopt;
  out.spec = spec.value;
  out.pneumatic = std::move(scene.value);
  out.jamming = std::move(jamming.value);
  return out;
}

}  // namespace palpa::bench
