// Scenes: speed against accuracy. Straight passes across the three-cube phantom with the
// thesis's triangle (the example scene) on the simulated board, in virtual time: each input sample
// (100 Hz, a pen tablet's rate) rendered and sent as one SetFingerTargets; every board tick, each
// finger's true output (the plant's) against the rule's target at the finger's current position.
// Passes run along the cubes' mid-line and along a second line 15 mm below it, where the
// triangle's third finger crosses the cubes. Prints, per speed and per finger, the error (RMS and
// 95th percentile, of the scene's target range), the finger's speed where it meets cube B's near
// face, and the edge lag there (how far the finger travels past the point where the rule's
// target crosses half of its change before its true output does) — each pass on the
// fingers' nominal curves without step shaping, and with every finger calibrated on its rig as
// palpa calibrate does and the calibration applied (scene_pass.h).
//   palpa_scene_bench SCENE.json
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scene_pass.h"
#include "scene_paths.h"

namespace pb = palpa::bench;
namespace pp = palpa::protocol;
namespace ph = palpa::host;

using pb::HandLike;
using pb::kEndX;
using pb::kStartX;
using pb::Straight;

namespace {

double Percentile(std::vector<double> v, double p);

/// "RMS | p95 | edge lag" of one pass, as Markdown cells.
std::string Cells(const pb::FingerScore& r) {
  double sum = 0;
  for (double e : r.errors) sum += e * e;
  char lag[32] = "never";  // the output never reached half of the change while over B
  if (!r.meets_edge) std::snprintf(lag, sizeof(lag), "—");  // its path misses B's face
  if (!std::isnan(r.edge_lag_mm)) std::snprintf(lag, sizeof(lag), "%.2f mm", r.edge_lag_mm);
  char cells[96];
  std::snprintf(cells, sizeof(cells), " %.1f %% | %.1f %% | %s |",
                100 * std::sqrt(sum / static_cast<double>(r.errors.size())),
                100 * Percentile(r.errors, 0.95), lag);
  return cells;
}

double Percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[static_cast<size_t>(p * static_cast<double>(v.size() - 1))];
}

/// One pass along y = `y` on both boards: the fingers on their nominal curves with no step
/// shaping (as the scene was first measured), and each finger calibrated on its rig and applied.
/// A Markdown row per finger, with the finger's speed where it met B's face.
int Row(const ph::SceneRenderer& scene, bool jamming, const std::vector<uint8_t>& fingers,
        const std::string& name, const std::vector<double>& path, double y, double range) {
  std::vector<std::string> rows;
  for (const bool calibrated : {false, true}) {
    pb::ScenePass pass(scene, jamming, calibrated, fingers);
    if (!pass.ok()) return 1;
    const pb::PassResult r = pass.Pass(path, y, range);
    for (size_t f = 0; f < fingers.size(); ++f) {
      if (!calibrated) {
        char speed[32] = "—";
        if (!std::isnan(r[f].edge_speed_mm_s))
          std::snprintf(speed, sizeof(speed), "%.1f mm/s", r[f].edge_speed_mm_s);
        rows.push_back("| " + name + " | " + std::to_string(fingers[f]) + " | " + speed + " |");
      }
      rows[f] += Cells(r[f]);
    }
  }
  for (const std::string& row : rows) std::printf("%s\n", row.c_str());
  std::fflush(stdout);
  return 0;
}

/// The table of one scene's passes along y = `y`: straight at each speed, then hand-like.
int Table(const ph::SceneRenderer& scene, bool jamming, const std::vector<uint8_t>& fingers,
          const std::string& title, double y) {
  const auto [lo, hi] = pb::TargetRange(scene);  // along the mid-line: every table the same
  std::printf(
      "\n%s on palpa-sim %s, plant level 3, unit %u; passes along y = %g mm from x = %g to %g mm,"
      " input at %d Hz; target range %.3f %s\n\n",
      title.c_str(), jamming ? "thesis-jamming-2" : "thesis-pneumatic-3", pb::kUnit, y, kStartX,
      kEndX, 1000 / pb::kInputEveryMs, hi - lo, jamming ? "N/mm" : "mm");
  std::printf(
      "| pass | finger | speed at B | nominal: error RMS | p95 | edge lag at B | fingers "
      "calibrated: "
      "error RMS | p95 | edge lag at B |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const double speed : {5.0, 10.0, 20.0, 30.0, 60.0}) {
    char name[48];
    std::snprintf(name, sizeof(name), "straight, %g mm/s", speed);
    if (Row(scene, jamming, fingers, name, Straight(speed), y, hi - lo) != 0) return 1;
  }
  for (const double speed : {10.0, 30.0}) {
    char name[48];
    std::snprintf(name, sizeof(name), "hand-like, %g mm/s ± 50 %%", speed);
    if (Row(scene, jamming, fingers, name, HandLike(speed), y, hi - lo) != 0) return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int status = 0;
  const auto scenes = pb::LoadBenchScenes(argc, argv, "palpa_scene_bench", &status);
  if (!scenes) return status;
  // Along the mid-line fingers 0 and 1 cross the cubes; along the second line finger 2 does.
  for (const double y : {pb::kMidLineY, pb::kSecondLineY}) {
    if (Table(scenes->pneumatic, false, scenes->spec.board_fingers, "scene " + scenes->spec.name,
              y) != 0)
      return 1;
  }
  return Table(scenes->jamming, true, {0, 1},
               "the jamming pair (20 mm, a 4 mm disc) on the same tissue", pb::kMidLineY);
}
