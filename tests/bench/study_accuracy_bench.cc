// Studies: where the controller's accuracy meets the person's. A two-finger detection study in
// deformation (mm, the fingers' output unit) whose "tumour" finger is 5 … 30 % deeper than the
// other, run by the study library's runner on palpa-sim (a held-out unit, plant level 3) and
// answered by the simulated participant (Weber fraction 15 %), which feels the true output from
// the truth channel. Three displays: the fingers on their nominal curves; calibrated by palpa
// calibrate's protocol on their rig (scene_pass.h) without the compensator; and with it. Per
// display and difference: the display's error (true output against requested, from the truth
// channel at the answer) and the participant's accuracy per finger position with its Wilson
// interval. Prints a Markdown table and writes it, with an SVG chart, to docs/studies.md.
//   palpa_study_accuracy_bench [TRIALS_PER_CELL (a multiple of 3, 3 … 300)] [SPEED]
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "doc_block.h"
#include "palpa/host/device.h"
#include "palpa/host/field_text.h"
#include "palpa/host/sim_truth.h"
#include "palpa/host/study_participant.h"
#include "palpa/host/study_stats.h"
#include "scene_pass.h"

namespace pb = palpa::bench;
namespace ph = palpa::host;
namespace fs = std::filesystem;

namespace {

constexpr double kReferenceMm =
    1.5;  ///< the softer finger: about 30 kPa, the thesis's firmer level
const char kConfig[] = "thesis-pneumatic-3";

enum class Display { kNominal, kCalibrated, kCompensated };
const char* DisplayName(Display d) {
  return d == Display::kNominal      ? "nominal fingers"
         : d == Display::kCalibrated ? "calibrated, no compensation"
                                     : "calibrated, compensated";
}

/// The simulated participant, and beside each answer the true outputs it was given from.
class Recording final : public ph::StudyParticipant {
 public:
  Recording(ph::TruthReader& truth, uint32_t seed)
      : truth_(truth), person_(truth, [seed] {
          ph::SimulatedParticipantOptions o;
          o.seed = seed;
          o.explore_s = 0.15;
          return o;
        }()) {}
  void Feel(const ph::TrialPrompt& t, int f, ph::BoardClock& c, double until) override {
    person_.Feel(t, f, c, until);
  }
  ph::Result<ph::StudyAnswer> Answer(const ph::TrialPrompt& t, ph::BoardClock& c) override {
    auto a = person_.Answer(t, c);
    ph::TruthReader::Sample s;
    if (truth_.Latest(s)) felt_from[t.index] = s.outputs;
    return a;
  }
  void Refused(const std::string& why) override { person_.Refused(why); }
  bool Break(int done, int total) override { return person_.Break(done, total); }
  std::map<int, std::vector<double>> felt_from;  ///< trial index → true outputs (mm)

 private:
  ph::TruthReader& truth_;
  ph::SimulatedParticipant person_;
};

/// The study: every finger equal, or finger 1 or 2 deeper by `difference`, in one simultaneous
/// block; resets short, the settle band wide enough for a nominal regulator's static error.
std::string StudyText(double difference, int repetitions) {
  const double hi = kReferenceMm * (1 + difference);
  char text[900];
  std::snprintf(text, sizeof(text),
                R"({"schema": "palpa-study", "schema_version": 1, "name": "accuracy-%.0f",
  "finger_kind": "pneumatic", "fingers": 2, "unit": "mm", "cap_kpa": 80,
  "reset": {"hold_ms": 200}, "settle": {"band_kpa": 6},
  "conditions": [{"values": [%.4f, %.4f]}, {"values": [%.4f, %.4f]}, {"values": [%.4f, %.4f]}],
  "blocks": [{"name": "at-once", "mode": "simultaneous", "repetitions": %d}]})",
                100 * difference, kReferenceMm, kReferenceMm, hi, kReferenceMm, kReferenceMm, hi,
                repetitions);
  return text;
}

struct Cell {
  Display display;
  double difference = 0;       ///< requested, of the softer finger
  ph::DetectionCounts counts;  ///< per finger position
  ph::Proportion accuracy;
  ph::Interval interval;
  double value_rms = 0;      ///< |true − requested| / requested, RMS over every position (%)
  double contrast_err = 0;   ///< RMS of true − requested difference, of the requested one (%)
  double felt_contrast = 0;  ///< mean true difference of the tumour trials (% of the softer)
  double spurious = 0;       ///< mean |true difference| of the equal trials (% of the softer)
  int trials = 0;
};

/// Applies the display's calibration (or none) to the study's two fingers.
bool Prepare(ph::Device& device, Display d) {
  if (d == Display::kNominal) return true;
  for (uint8_t f : {0, 1}) {
    const ph::CalibrationFile* made = pb::ScenePass::FingerCalibrationFor(kConfig, f);
    if (made == nullptr) return false;
    ph::CalibrationFile file = *made;
    const auto finger = device.ReadFinger(f);
    if (!finger.ok()) return std::fprintf(stderr, "%s\n", finger.message.c_str()), false;
    file.actuator_serial = ph::FieldText(finger.value.actuator_serial);  // the same unit's
    if (d == Display::kCalibrated) {
      file.compensator = palpa::protocol::CompensatorKind::kNone;
      file.compensator_params.clear();
    }
    const ph::Outcome o = device.ApplyCalibration(f, file);
    if (!o.ok()) return std::fprintf(stderr, "finger %u: %s\n", f, o.message.c_str()), false;
  }
  return true;
}

bool RunCell(ph::Device& device, ph::TruthReader& truth, Cell& cell, int repetitions,
             uint32_t seed) {
  const auto study = ph::ParseStudy(StudyText(cell.difference, repetitions));
  if (!study.ok()) return std::fprintf(stderr, "%s\n", study.message.c_str()), false;
  Recording person(truth, seed);
  ph::StudyRunOptions o;
  o.out_dir = "/tmp/palpa-study-accuracy-" + std::to_string(getpid()) + "-" + std::to_string(seed);
  fs::remove_all(o.out_dir);
  o.participant = "S" + std::to_string(seed);
  o.board = std::string("sim:") + kConfig;
  o.use_calibrations = false;
  const ph::Outcome run = ph::RunStudy(device, study.value, person, o);
  if (!run.ok()) return std::fprintf(stderr, "%s\n", run.message.c_str()), false;
  const auto records = ph::ReadSessionDir(o.out_dir);
  fs::remove_all(o.out_dir);
  if (!records.ok()) return std::fprintf(stderr, "%s\n", records.message.c_str()), false;
  double value_sq = 0, contrast_sq = 0, felt = 0, spurious = 0;
  int positions = 0, tumours = 0, equal = 0;
  for (const ph::TrialRecord& t : records.value.trials) {
    const auto truth_at = person.felt_from.find(static_cast<int>(t.index));
    if (truth_at == person.felt_from.end() || truth_at->second.size() < 2) {
      std::fprintf(stderr, "trial %lld: no truth at the answer\n", static_cast<long long>(t.index));
      return false;
    }
    const std::vector<double>& y = truth_at->second;
    for (size_t f = 0; f < 2; ++f) {
      const double e = (y[f] - t.stimulus[f]) / t.stimulus[f];
      value_sq += e * e;
      const bool marked = t.answer.fingers[f];
      ph::DetectionCounts& n = cell.counts;
      (t.expected[f] ? (marked ? n.tp : n.fn) : (marked ? n.fp : n.tn)) += 1;
      ++positions;
    }
    const size_t hi = t.expected[1] ? 1 : 0, lo = 1 - hi;
    const double requested = t.stimulus[hi] - t.stimulus[lo], shown = y[hi] - y[lo];
    if (t.expected[0] || t.expected[1]) {
      const double e = (shown - requested) / requested;
      contrast_sq += e * e;
      felt += shown / y[lo];
      ++tumours;
    } else {
      spurious += std::fabs(shown) / std::min(y[0], y[1]);
      ++equal;
    }
  }
  cell.trials = static_cast<int>(records.value.trials.size());
  cell.accuracy = ph::Accuracy(cell.counts);
  cell.interval = ph::WilsonInterval(cell.accuracy);
  cell.value_rms = 100 * std::sqrt(value_sq / positions);
  cell.contrast_err = 100 * std::sqrt(contrast_sq / tumours);
  cell.felt_contrast = 100 * felt / tumours;
  cell.spurious = 100 * spurious / equal;
  return true;
}

std::string Row(const Cell& c) {
  char row[400];
  std::snprintf(row, sizeof(row),
                "| %s | %.0f %% | %d | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %.1f %% "
                "| %.1f %% [%.1f, %.1f] (%.0f/%.0f) |\n",
                DisplayName(c.display), 100 * c.difference, c.trials, c.value_rms, c.contrast_err,
                c.felt_contrast, c.spurious, 100 * ph::Sensitivity(c.counts).value(),
                100 * ph::Specificity(c.counts).value(), 100 * c.accuracy.value(),
                100 * c.interval.lo, 100 * c.interval.hi, c.accuracy.k, c.accuracy.n);
  return row;
}

std::string ChartSvg(const std::vector<Cell>& cells) {
  const char* colours[] = {"#c0392b", "#2471a3", "#1e8449"};
  ph::Chart accuracy{"The simulated participant's accuracy per finger position (Wilson 95 %)",
                     "requested difference (% of the softer finger)",
                     "accuracy (%)",
                     {},
                     {},
                     780,
                     300};
  ph::Chart error{"The display's error at the answer (truth channel)",
                  "requested difference (% of the softer finger)",
                  "error (% of the value)",
                  {},
                  {},
                  780,
                  320};
  for (const Display d : {Display::kNominal, Display::kCalibrated, Display::kCompensated}) {
    const int i = static_cast<int>(d);
    ph::Series acc{DisplayName(d), {}, colours[i], false, true, true};
    ph::Series err{std::string(DisplayName(d)) + ": value", {}, colours[i], false, true, true};
    ph::Series spread{
        std::string(DisplayName(d)) + ": between equal fingers", {}, colours[i], true};
    for (const Cell& c : cells) {
      if (c.display != d) continue;
      const double x = 100 * c.difference + 0.4 * (i - 1);  // the intervals side by side
      acc.points.push_back({x, 100 * c.accuracy.value()});
      err.points.push_back({x, c.value_rms});
      spread.points.push_back({x, c.spurious});
      accuracy.series.push_back(
          {"", {{x, 100 * c.interval.lo}, {x, 100 * c.interval.hi}}, colours[i], false, false});
    }
    accuracy.series.push_back(acc);
    error.series.push_back(err);
    error.series.push_back(spread);
  }
  error.series.push_back({"the Weber fraction (15 %)", {{5, 15}, {30, 15}}, "#7f8c8d", true});
  return ph::RenderSvgPanels({accuracy, error},
                             "A two-finger detection study on palpa-sim: accuracy against the "
                             "display's error");
}

}  // namespace

int main(int argc, char** argv) {
  const int per_cell = argc > 1 ? std::atoi(argv[1]) : 300;
  const double speed = argc > 2 ? std::atof(argv[2]) : 80;
  if (argc > 3 || per_cell < 3 || per_cell > 300 || per_cell % 3 != 0 || !(speed > 0)) {
    std::fprintf(stderr,
                 "usage: palpa_study_accuracy_bench [TRIALS_PER_CELL (a multiple of 3, 3 … 300)] "
                 "[SPEED]\n");
    return 2;
  }
  const std::string unit = std::to_string(pb::kUnit);
  char speed_text[32];
  std::snprintf(speed_text, sizeof(speed_text), "%g", speed);
  std::string address;
  auto transport = ph::LaunchSim(
      kConfig, {"--unit", unit, "--seed", unit, "--speed", speed_text, "--truth-every-ms", "5"},
      &address);
  if (!transport.ok()) return std::fprintf(stderr, "%s\n", transport.message.c_str()), 1;
  ph::DeviceOptions options;
  options.use_calibrations = false;
  auto device = ph::Device::Attach(std::move(transport.value), options);
  if (!device.ok()) return std::fprintf(stderr, "%s\n", device.message.c_str()), 1;
  ph::TruthReader truth(2000);
  if (!truth.Connect(address)) return std::fprintf(stderr, "no truth at %s\n", address.c_str()), 1;

  const char* header =
      "| display | requested difference | trials | value error (RMS) | difference error (RMS) "
      "| difference shown | spurious difference (equal fingers) | Se | Sp | accuracy [Wilson 95 %] "
      "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  std::printf(
      "\npalpa-sim %s, plant level 3, unit %u, at %gx; reference %.1f mm; %d trials per "
      "cell\n\n%s",
      kConfig, pb::kUnit, speed, kReferenceMm, per_cell, header);
  std::vector<Cell> cells;
  uint32_t seed = 1;
  for (const Display d : {Display::kNominal, Display::kCalibrated, Display::kCompensated}) {
    if (!Prepare(*device.value, d)) return 1;
    for (const double difference : {0.05, 0.10, 0.15, 0.20, 0.30}) {
      Cell c;
      c.display = d;
      c.difference = difference;
      if (!RunCell(*device.value, truth, c, per_cell / 3, seed++)) return 1;
      std::printf("%s", Row(c).c_str());
      std::fflush(stdout);
      cells.push_back(c);
    }
  }
  std::string table = header;
  for (const Cell& c : cells) table += Row(c);
  if (!ph::WriteFileWhole("docs/study_accuracy.svg", ChartSvg(cells)).ok() ||
      !pb::ReplaceBlock("docs/studies.md", "study-accuracy", table))
    return std::fprintf(stderr, "cannot write docs/studies.md or its chart\n"), 1;
  return 0;
}
