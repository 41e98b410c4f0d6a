// Scenes: prediction off and on. The example scene's straight and hand-like passes on the
// simulated board in virtual time (scene_pass.h), every finger calibrated by palpa calibrate's
// protocol and applied (steps shaped), each pass run twice on the same unit: rendering each input
// sample as it is, and rendering its prediction over the fingers' calibrated display delay
// (scene_predict.h). Prints, per pass, the error (RMS of every finger, of the target range), the
// edge lag at cube B's near face (finger 0, first crossing) and the worst edge lag at any cube face
// any finger crosses either way (scene_edges.h), with prediction off and on; the worst change an
// edge's lag takes from off to on; and how many samples were predicted. Then every edge of the
// issue's goal pass (hand-like, 30 mm/s) off and on. Then the jamming pair.
//   palpa_scene_predict_bench SCENE.json
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scene_edges.h"
#include "scene_pass.h"
#include "scene_paths.h"

namespace pb = palpa::bench;
namespace ph = palpa::host;

namespace {

struct Scored {
  double rms = 0;
  double lag_b = NAN;                   ///< finger 0 at B's near face, first crossing
  double worst = 0;                     ///< the largest |lag| of any edge
  size_t never = 0;                     ///< edges the output did not cross near the rule's
  std::vector<pb::EdgeCrossing> edges;  ///< every finger's, in finger order
  size_t predicted = 0, samples = 0;
  double horizon_s = 0;
  size_t fell_back = 0;  ///< fingers whose line's shaping fell back during the pass
};

/// One pass on a calibrated board, prediction off or on, scored.
bool Run(const ph::SceneRenderer& scene, bool jamming, const std::vector<uint8_t>& fingers,
         const std::vector<double>& path, double range, bool predict, double tremor_mm,
         Scored* out) {
  pb::ScenePass pass(scene, jamming, true, fingers);
  if (!pass.ok() || (predict && !pass.Predict())) return false;
  pass.SetTremor(tremor_mm);
  const pb::PassResult r = pass.Pass(path, pb::kMidLineY, range);
  double sum = 0;
  size_t n = 0;
  for (size_t f = 0; f < r.size(); ++f) {
    for (double e : r[f].errors) sum += e * e, ++n;
    const double dx = pass.scene().layout().fingers[f].dx_mm;
    const auto target = [&](double at) {
      return pass.scene().Render({0, at - dx, pb::kMidLineY, 1})[f].mapped.target / 1000.0;
    };
    for (const pb::EdgeCrossing& e : pb::EdgeCrossings(f, r[f].place, r[f].output, target, range)) {
      out->edges.push_back(e);
      if (std::isnan(e.lag_mm)) {
        ++out->never;
        continue;
      }
      out->worst = std::max(out->worst, std::fabs(e.lag_mm));
      if (f == 0 && e.face_mm == 54 && e.direction > 0 && std::isnan(out->lag_b))
        out->lag_b = e.lag_mm;
    }
  }
  out->rms = std::sqrt(sum / static_cast<double>(n));
  out->predicted = pass.predicted();
  out->samples = pass.samples();
  out->horizon_s = pass.horizon_s();
  out->fell_back = pass.FellBack();
  return true;
}

std::string Mm(double v) {
  char b[32];
  if (std::isnan(v)) return "never";
  std::snprintf(b, sizeof(b), "%.2f mm", v);
  return b;
}

/// Each edge's lag off and on, a Markdown row each.
std::vector<std::string> EdgeRows(const Scored& off, const Scored& on) {
  std::vector<std::string> rows;
  for (size_t k = 0; k < off.edges.size() && k < on.edges.size(); ++k) {
    const pb::EdgeCrossing& a = off.edges[k];
    const double change = std::fabs(on.edges[k].lag_mm) - std::fabs(a.lag_mm);
    char row[160];
    std::snprintf(row, sizeof(row), "| %zu | %g mm %s | %s | %s | %s |", a.finger, a.face_mm,
                  a.direction > 0 ? "→" : "←", Mm(a.lag_mm).c_str(), Mm(on.edges[k].lag_mm).c_str(),
                  std::isnan(change) ? "—" : (change >= 0 ? "+" + Mm(change) : Mm(change)).c_str());
    rows.push_back(row);
  }
  return rows;
}

int Row(const ph::SceneRenderer& scene, bool jamming, const std::vector<uint8_t>& fingers,
        const std::string& name, const std::vector<double>& path, double range, double tremor,
        double* horizon_s, std::vector<std::string>* notes, std::vector<std::string>* edges) {
  Scored off, on;
  if (!Run(scene, jamming, fingers, path, range, false, tremor, &off) ||
      !Run(scene, jamming, fingers, path, range, true, tremor, &on))
    return 1;
  *horizon_s = on.horizon_s;
  if (edges != nullptr) *edges = EdgeRows(off, on);
  // The same path crosses the same edges in the same order, whatever is rendered.
  double change = -INFINITY;
  std::string where;
  for (size_t k = 0; k < off.edges.size() && k < on.edges.size(); ++k) {
    const double a = std::fabs(off.edges[k].lag_mm), b = std::fabs(on.edges[k].lag_mm);
    if (std::isnan(a) || std::isnan(b) || !(b - a > change)) continue;
    change = b - a;
    char w[64];
    std::snprintf(w, sizeof(w), " (finger %zu, %g mm %s)", off.edges[k].finger,
                  off.edges[k].face_mm, off.edges[k].direction > 0 ? "→" : "←");
    where = w;
  }
  char row[400];
  std::snprintf(
      row, sizeof(row), "| %s | %.1f %% | %s | %s | %.1f %% | %s | %s | %+.2f mm%s | %zu of %zu |",
      name.c_str(), 100 * off.rms, Mm(off.lag_b).c_str(), Mm(off.worst).c_str(), 100 * on.rms,
      Mm(on.lag_b).c_str(), Mm(on.worst).c_str(), change, where.c_str(), on.predicted, on.samples);
  std::printf("%s\n", row);
  if (off.fell_back + on.fell_back > 0) {
    char note[160];
    std::snprintf(note, sizeof(note),
                  "%s: fingers whose line's shaped steps fell back to slew-limited ones: %zu off, "
                  "%zu on",
                  name.c_str(), off.fell_back, on.fell_back);
    notes->push_back(note);
  }
  if (off.never + on.never > 0) {
    char note[160];
    std::snprintf(note, sizeof(note),
                  "%s: edges the output did not cross within %g mm of the rule: %zu off, %zu on",
                  name.c_str(), pb::kEdgeSearchMm, off.never, on.never);
    notes->push_back(note);
  }
  std::fflush(stdout);
  return 0;
}

int Table(const ph::SceneRenderer& scene, bool jamming, const std::vector<uint8_t>& fingers,
          const std::string& title) {
  const auto [lo, hi] = pb::TargetRange(scene);
  std::printf(
      "\n%s on palpa-sim %s, plant level 3, unit %u, every finger calibrated; input at %d Hz; "
      "target range %.3f %s\n\n",
      title.c_str(), jamming ? "thesis-jamming-2" : "thesis-pneumatic-3", pb::kUnit,
      1000 / pb::kInputEveryMs, hi - lo, jamming ? "N/mm" : "mm");
  std::printf(
      "| pass | off: error RMS | edge lag at B | worst edge lag | on: error RMS | edge lag at B | "
      "worst edge lag | worst change, off → on | predicted |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  double horizon = 0;
  struct Pass {
    std::string name;
    std::vector<double> path;
    double tremor;
    bool every_edge = false;  ///< the pass the issue's goal is set on: each edge listed
  };
  std::vector<Pass> passes;
  for (const double v : {10.0, 20.0, 30.0, 45.0, 60.0}) {
    char name[64];
    std::snprintf(name, sizeof(name), "straight, %g mm/s", v);
    passes.push_back({name, pb::Straight(v), 0});
  }
  for (const double v : {10.0, 20.0, 30.0, 45.0}) {
    char name[64];
    std::snprintf(name, sizeof(name), "hand-like, %g mm/s ± 50 %%", v);
    passes.push_back({name, pb::HandLike(v), 0, v == 30});
  }
  for (const double tremor : {0.05, 0.2}) {
    char name[64];
    std::snprintf(name, sizeof(name), "hand-like, 30 mm/s, %g mm tremor", tremor);
    passes.push_back({name, pb::HandLike(30), tremor});
  }
  std::vector<std::string> notes, edges;
  std::string listed;
  for (const Pass& p : passes) {
    if (Row(scene, jamming, fingers, p.name, p.path, hi - lo, p.tremor, &horizon, &notes,
            p.every_edge ? &edges : nullptr) != 0)
      return 1;
    if (p.every_edge) listed = p.name;
  }
  std::printf("\nprediction horizon: %.1f ms (the fingers' calibrated display delay)\n",
              horizon * 1e3);
  for (const std::string& n : notes) std::printf("%s\n", n.c_str());
  std::printf(
      "\nevery edge of %s, finger by finger and face by face, each face's crossings in turn:\n\n"
      "| finger | face | off: edge lag | on: edge lag | change, off → on |\n"
      "|---:|---|---:|---:|---:|\n",
      listed.c_str());
  for (const std::string& e : edges) std::printf("%s\n", e.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int status = 0;
  const auto scenes = pb::LoadBenchScenes(argc, argv, "palpa_scene_predict_bench", &status);
  if (!scenes) return status;
  if (Table(scenes->pneumatic, false, scenes->spec.board_fingers, "scene " + scenes->spec.name) !=
      0)
    return 1;
  return Table(scenes->jamming, true, {0, 1},
               "the jamming pair (20 mm, a 4 mm disc) on the same tissue");
}
