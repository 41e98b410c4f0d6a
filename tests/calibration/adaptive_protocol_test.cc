// The adaptive protocol on the in-process simulated rig at the thesis's press speed: it stops on
// its own cross-validated estimate within the budget, and the simulator's truth (which it never
// sees) confirms the map; an interrupted run resumes with the same choices; a whole calibration
// with it gives a file the library accepts.
#include <cmath>
#include <string>

#include "calibration_experiments.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace pt = palpa::testing;
namespace ph = palpa::host;

TEST_GROUP(AdaptiveProtocol){};

TEST(AdaptiveProtocol, StopsOnItsOwnEstimateWithinTheBudgetAndTheTruthAgrees) {
  pt::SimRig sim({"thesis-5finger", pt::kJammingFinger, 31, 31, {}});
  cal::Rig rig = sim.rig();
  double zero = 0;
  cal::RigStatus s = cal::ZeroOnVentedSurface(rig, pt::kJammingFinger, {}, &zero);
  CHECK_TEXT(s.ok(), s.message.c_str());
  nlohmann::json state;
  std::vector<cal::MapPress> presses;
  cal::MapEstimate estimate;
  const cal::AdaptiveOptions options;
  s = cal::RunAdaptiveMap(rig, pt::kJammingFinger, zero, cal::PressSettings{}, options, state, {},
                          &presses, &estimate);
  CHECK_TEXT(s.ok(), s.message.c_str());
  CHECK(static_cast<int>(presses.size()) <= options.max_cycles);
  CHECK(static_cast<int>(presses.size()) >= options.min_cycles);
  CHECK(estimate.repeated_conditions >= 1);  // it learned its press noise
  CHECK(estimate.map_error <= options.target_error);
  const pt::MapScore truth = pt::ScoreSurface(presses, sim);
  CHECK_TEXT(truth.rms <= 0.03, std::to_string(truth.rms).c_str());
  // The thesis grid at one repeat, read bilinearly, is worse on the same unit.
  pt::SimRig grid_sim({"thesis-5finger", pt::kJammingFinger, 31, 31, {}});
  cal::Rig grid_rig = grid_sim.rig();
  CHECK(cal::ZeroOnVentedSurface(grid_rig, pt::kJammingFinger, {}, &zero).ok());
  nlohmann::json grid_state;
  std::vector<cal::MapPress> grid;
  CHECK(cal::RunGridMap(grid_rig, pt::kJammingFinger, zero, cal::PressSettings{}, {0, 10, 20},
                        {0, -50, -100}, 1, grid_state, {}, &grid)
            .ok());
  CHECK(pt::ScoreBilinear(cal::SummariseConditions(grid), grid_sim).rms > 2 * truth.rms);
}

TEST(AdaptiveProtocol, AnInterruptedMapResumesWithTheSameChoices) {
  const cal::PressSettings fast{2, 2, 0.5};
  cal::AdaptiveOptions options;
  options.max_cycles = 10;
  auto run = [&](pt::SimRig& sim, nlohmann::json& state, int lose_force_after,
                 std::vector<cal::MapPress>* presses) {
    cal::Rig rig = sim.rig();
    double zero = 0;
    if (!cal::ZeroOnVentedSurface(rig, pt::kJammingFinger, {}, &zero).ok())
      return cal::RigStatus::Fail(ph::Status::kUnavailable, "zero");
    cal::MapHooks hooks;
    hooks.after_press = [&](const std::vector<cal::MapPress>& p) {
      if (static_cast<int>(p.size()) == lose_force_after) sim.force_lost = true;
    };
    cal::MapEstimate e;
    return cal::RunAdaptiveMap(rig, pt::kJammingFinger, zero, fast, options, state, hooks, presses,
                               &e);
  };
  nlohmann::json whole_state, state;
  std::vector<cal::MapPress> whole, first, second;
  pt::SimRig a({"thesis-5finger", pt::kJammingFinger, 5, 5, {}});
  CHECK(run(a, whole_state, -1, &whole).ok());
  pt::SimRig b({"thesis-5finger", pt::kJammingFinger, 5, 5, {}});
  const cal::RigStatus stopped = run(b, state, 6, &first);
  CHECK_FALSE(stopped.ok());
  CHECK(stopped.message.find("force sensor lost") != std::string::npos);
  LONGS_EQUAL(6, state["presses"].size());  // every finished press is in the journal
  pt::SimRig c({"thesis-5finger", pt::kJammingFinger, 5, 5, {}});
  CHECK(run(c, state, -1, &second).ok());
  // The journal's presses are kept as they were, and the first choice after them is the one the
  // uninterrupted run made; later ones follow new readings (new noise), within the same budget.
  CHECK(second.size() > 6);
  CHECK(static_cast<int>(second.size()) <= options.max_cycles);
  for (size_t i = 0; i <= 6; ++i) {
    DOUBLES_EQUAL(whole[i].bias_kpa, second[i].bias_kpa, 1e-9);
    DOUBLES_EQUAL(whole[i].vacuum_kpa, second[i].vacuum_kpa, 1e-9);
  }
  for (size_t i = 0; i < 6; ++i) DOUBLES_EQUAL(first[i].stiffness, second[i].stiffness, 0);
}

TEST(AdaptiveProtocol, AWholeCalibrationWithItGivesAFileTheLibraryAccepts) {
  pt::SimRig sim({"thesis-5finger", pt::kJammingFinger, 2, 2, {}});
  cal::Rig rig = sim.rig();
  cal::Journal journal;
  cal::CalibrationRun run;
  const cal::RunInfo info{"JAM-1", 1, "2026-11-22T12:00:00Z", "sim", "JAM-1.csv"};
  const cal::RigStatus s = cal::RunCalibration(rig, pt::kJammingFinger, pt::ShortAdaptiveProtocol(),
                                               info, journal, nullptr, &run);
  CHECK_TEXT(s.ok(), s.message.c_str());
  STRCMP_EQUAL("adaptive", run.file.quality.protocol.c_str());
  LONGS_EQUAL(run.map.size(), run.file.quality.cycles);
  CHECK(run.file.quality.map_error.has_value());
  CHECK(run.file.quality.rig_time_s > 60);
  LONGS_EQUAL(4, run.file.quality.checks.size());  // no previous calibration: four detectors
  for (const ph::QualityCheck& k : run.file.quality.checks) CHECK_TEXT(k.passed, k.detail.c_str());
  CHECK(run.file.recommended_bias_pa.has_value());
  const auto written = ph::SerializeCalibration(run.file);
  CHECK_TEXT(written.ok(), written.message.c_str());
}
