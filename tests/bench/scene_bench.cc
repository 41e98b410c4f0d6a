// Scenes: speed against accuracy. Straight passes across the three-cube phantom with the
// thesis's triangle (the example scene) on the simulated board, in virtual time: each input sample
// (100 Hz, a pen tablet's rate) rendered and sent as one SetFingerTargets; every board tick, each
// finger's true output (the plant's) against the rule's target at the finger's current position.
// Prints, per speed, the error (RMS and 95th percentile, of the scene's target range) and the edge
// lag at cube B's leading edge (how far finger 0 travels past the point where the rule's target
// crosses half of its change before its true output does).
//   palpa_scene_bench SCENE.json
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "palpa/hal/fake/fakes.h"
#include "palpa/host/scene_file.h"
#include "palpa/protocol/codec.h"
#include "sim_board.h"

namespace ps = palpa::sim;
namespace pp = palpa::protocol;
namespace ph = palpa::host;

namespace {

constexpr int kInputEveryMs = 10;
constexpr double kStartX = 20, kEndX = 100, kY = 15;

struct PassResult {
  std::vector<double> errors;  ///< |true − target| / range, every tick, every finger
  double edge_lag_mm = NAN;
};

class Bench {
 public:
  Bench(const ph::SceneRenderer& scene, bool jamming) : scene_(scene), jamming_(jamming) {
    ps::SimBoardOptions o;
    o.config = jamming ? "thesis-jamming-2" : "thesis-pneumatic-3";
    o.plant.level = 3;
    o.plant.unit = 12;  // a held-out unit, not the nominal one
    o.plant.seed = 7;
    std::string error;
    sim_ = ps::SimBoard::Create(o, link_, &error);
    if (!sim_) std::fprintf(stderr, "scene bench: %s\n", error.c_str());
    Send(pp::Hello{1, 0}, false);
    sim_->Advance(5);
  }
  bool ok() const { return sim_ != nullptr; }

  /// A path: the input's x at each millisecond of the pass (after settling at the first).
  PassResult Pass(const std::vector<double>& path, double range_mm) {
    PassResult r;
    // Settle at the start (the first target re-homes the fingers), then the pass.
    const int settle_ms = 1500;
    const int pass_ms = static_cast<int>(path.size()) - 1;
    double previous_true = 0;
    const double edge = 54;  // cube B's near face, where finger 0 meets it
    const double dx0 = scene_.layout().fingers[0].dx_mm;  // finger 0 from the input
    const double before = Target0(edge - 3 - dx0), on = Target0(edge + 3 - dx0);
    const double half = (before + on) / 2;
    double rule_cross = NAN;
    for (int ms = -settle_ms; ms <= pass_ms; ++ms) {
      const double x = path[static_cast<size_t>(std::max(0, ms))];
      if (ms % kInputEveryMs == 0) SendTargets(x);
      if (ms % 20 == 0) Send(pp::Heartbeat{1, ++generation_}, false);
      sim_->Advance(1000);
      link_.tx.clear();
      if (ms < 0) continue;
      const auto truth = sim_->plant().Truth();
      const auto now = scene_.Render({0, x, kY, 1});
      for (size_t f = 0; f < now.size(); ++f) {
        const double target = now[f].mapped.target / 1000.0;
        r.errors.push_back(std::fabs(True(truth, f) - target) / range_mm);
      }
      if (std::isnan(rule_cross) && now[0].mapped.target / 1000.0 >= half) rule_cross = x + dx0;
      const double true0 = True(truth, 0);
      if (std::isnan(r.edge_lag_mm) && !std::isnan(rule_cross) && previous_true < half &&
          true0 >= half)
        r.edge_lag_mm = x + dx0 - rule_cross;
      previous_true = true0;
    }
    return r;
  }

 private:
  /// A finger's true output in its unit: deformation (mm) or stiffness (N/mm).
  double True(const ps::PlantTruth& t, size_t f) const {
    return jamming_ ? t.fingers[f].stiffness_n_per_mm : t.fingers[f].deformation_mm;
  }
  double Target0(double x) const { return scene_.Render({0, x, kY, 1})[0].mapped.target / 1000.0; }
  void SendTargets(double x) {
    pp::SetFingerTargets t{};
    t.session = 1;
    t.generation = ++generation_;
    const auto renders = scene_.Render({0, x, kY, 1});
    const auto requests = scene_.Requests(renders);
    for (size_t f = 0; f < renders.size(); ++f) {
      t.entries[t.entry_count++] = {requests[f].finger,
                                    jamming_ ? pp::OutputUnit::kStiffnessMilliNewtonPerMm
                                             : pp::OutputUnit::kDeformationMicrometre,
                                    renders[f].mapped.target};
    }
    Send(t, false);
  }
  template <class M>
  void Send(const M& m, bool reliable) {
    uint8_t frame[pp::kMaxFrameSize];
    const auto n = pp::EncodeMessageFrame(
        m, reliable ? seq_++ : 0, reliable ? pp::flags::kReliable : 0, frame, sizeof(frame));
    link_.Inject(frame, n.value);
    sim_->Advance(sim_->now_us() % 1000 == 0 ? 1 : 0);  // dispatched between ticks
  }

  const ph::SceneRenderer& scene_;
  bool jamming_;
  palpa::hal::fake::FakeByteLink link_;
  std::unique_ptr<ps::SimBoard> sim_;
  uint8_t seq_ = 0;
  uint32_t generation_ = 0;
};

double Percentile(std::vector<double> v, double p);

/// A straight pass at a constant speed, a position per millisecond.
std::vector<double> Straight(double speed_mm_s) {
  std::vector<double> path;
  for (double x = kStartX; x <= kEndX; x += speed_mm_s / 1000) path.push_back(x);
  return path;
}

/// A hand-like pass: speed varying ±50 % about `speed` (a 2 s cycle), forward to 80 mm, a 0.5 s
/// stop, back to 60 mm (over cube B again), another stop, then on to the end.
std::vector<double> HandLike(double speed) {
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

void Row(const char* name, const PassResult& r) {
  double sum = 0;
  for (double e : r.errors) sum += e * e;
  char lag[32] = "never";  // the output never reached half of the change while over B
  if (!std::isnan(r.edge_lag_mm)) std::snprintf(lag, sizeof(lag), "%.2f mm", r.edge_lag_mm);
  std::printf("%-30s %8.1f %% %9.1f %% %13s\n", name,
              100 * std::sqrt(sum / static_cast<double>(r.errors.size())),
              100 * Percentile(r.errors, 0.95), lag);
}

double Percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[static_cast<size_t>(p * static_cast<double>(v.size() - 1))];
}

/// The table of one scene's passes: straight at each speed, then hand-like.
int Table(const ph::SceneRenderer& scene, bool jamming, const std::string& title) {
  // The scene's target range: from the softest to the stiffest target the rule gives a finger
  // on the tissue.
  double lo = 1e9, hi = -1e9;
  for (double x = 0; x <= 120; x += 0.25) {
    for (const auto& r : scene.Render({0, x, kY, 1})) {
      if (!r.touching) continue;  // off the tissue: released, not part of the range
      lo = std::min(lo, r.mapped.target / 1000.0);
      hi = std::max(hi, r.mapped.target / 1000.0);
    }
  }
  const char* unit = jamming ? "N/mm" : "mm";
  std::printf(
      "\n%s on palpa-sim %s, plant level 3, unit 12, nominal curves;\n"
      "passes along y = %g mm from x = %g to %g mm, input at %d Hz; target range %.3f %s\n",
      title.c_str(), jamming ? "thesis-jamming-2" : "thesis-pneumatic-3", kY, kStartX, kEndX,
      1000 / kInputEveryMs, hi - lo, unit);
  std::printf("%-30s %10s %11s %13s\n", "pass", "error RMS", "error p95", "edge lag (B)");
  for (const double speed : {5.0, 10.0, 20.0, 30.0, 60.0}) {
    Bench bench(scene, jamming);
    if (!bench.ok()) return 1;
    char name[48];
    std::snprintf(name, sizeof(name), "straight, %g mm/s", speed);
    Row(name, bench.Pass(Straight(speed), hi - lo));
  }
  for (const double speed : {10.0, 30.0}) {
    Bench bench(scene, jamming);
    if (!bench.ok()) return 1;
    char name[48];
    std::snprintf(name, sizeof(name), "hand-like, %g mm/s ±50 %%", speed);
    Row(name, bench.Pass(HandLike(speed), hi - lo));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: palpa_scene_bench SCENE.json\n");
    return 2;
  }
  const auto spec = ph::LoadScene(argv[1]);
  if (!spec.ok()) return std::fprintf(stderr, "%s\n", spec.message.c_str()), 1;
  const auto tissue = ph::LoadSceneTissue(spec.value);
  if (!tissue.ok()) return std::fprintf(stderr, "%s\n", tissue.message.c_str()), 1;
  std::vector<ph::RenderFinger> fingers;
  for (uint8_t f : spec.value.board_fingers)
    fingers.push_back(
        {f, {pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, f, pp::kNoLine}, {}});
  const auto scene = ph::SceneRenderer::Make(tissue.value, ph::MakeLayout(spec.value.layout),
                                             spec.value.rule, fingers);
  if (!scene.ok()) return std::fprintf(stderr, "%s\n", scene.message.c_str()), 1;
  if (Table(scene.value, false, "scene " + spec.value.name) != 0) return 1;
  // The jamming pair on the same tissue, 20 mm apart, N/mm over each finger's nominal curve.
  std::vector<ph::RenderFinger> pair;
  for (uint8_t f = 0; f < 2; ++f) {
    pair.push_back(
        {f,
         {pp::FingerKind::kJamming, pp::FingerMode::kTarget, f, static_cast<uint8_t>(f + 2)},
         {}});
  }
  const auto jamming =
      ph::SceneRenderer::Make(tissue.value, ph::JammingPairLayout(20, 4), {}, pair);
  if (!jamming.ok()) return std::fprintf(stderr, "%s\n", jamming.message.c_str()), 1;
  return Table(jamming.value, true, "the jamming pair (20 mm, a 4 mm disc) on the same tissue");
}
