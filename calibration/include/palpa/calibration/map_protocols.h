// The stiffness map of a jamming finger, taken two ways: the thesis's fixed grid (every bias ×
// vacuum, so many repeats each) and the adaptive protocol, which picks the next condition (or a
// repeat) where the map is least sure and stops once its cross-validated error reaches a target.
// Both keep every press, for the quality checks, in the journal (a stopped run resumes).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/calibration/procedures.h"
#include "palpa/calibration/stiffness_surface.h"
#include "palpa/host/calibration_file.h"

namespace palpa::calibration {

/// One press of the map, with what the quality checks need.
struct MapPress {
  double bias_kpa = 0, vacuum_kpa = 0;                    ///< commanded
  double measured_bias_kpa = 0, measured_vacuum_kpa = 0;  ///< line readings after the presses
  double stiffness = 0;                                   ///< N/mm
  double loop_area_mj = 0, r2 = 0;
  double residual_n = 0;    ///< loading fit's residual RMS
  double free_force_n = 0;  ///< reading clear of the surface before the press
  int readings = 0;         ///< loading readings the fit used
  double time_s = 0;        ///< rig time when the press began
};

struct PressSettings {
  double depth_mm = 3;      ///< thesis: 3 mm
  double speed_mm_s = 0.1;  ///< thesis: 0.1 mm/s
  double dwell_s = 3;       ///< at the condition before the first press
};

struct AdaptiveOptions {
  /// Stop once the map's estimated error (cross-validated, press noise taken out) is at most this.
  double target_error = 0.025;
  int min_cycles = 8;   ///< never stop before: the first surfaces know little of their own error
  int max_cycles = 18;  ///< the budget; the run says when it stopped on it short of the target
  int bias_steps = 9;   ///< candidate lattice over the box (2.5 kPa × 5 kPa by default)
  int vacuum_steps = 21;
  MapBox box{};
};

/// What the rig can say of its map: leave-one-condition-out error, the press-to-press noise from
/// repeated conditions (0 without any), and the map's own error with that noise taken out.
struct MapEstimate {
  double cv_error = 1;
  double press_noise = 0;
  double map_error = 1;
  int cycles = 0;
  int conditions = 0;
  int repeated_conditions = 0;
};
MapEstimate EstimateMap(const std::vector<MapPress>& presses, const MapBox& box);
/// The same from a surface already fitted to those presses.
MapEstimate EstimateMap(const std::vector<MapPress>& presses, const StiffnessSurface& surface);

std::vector<MapSample> StiffnessSamples(const std::vector<MapPress>& presses);

/// One condition's presses summarised, in the rig's units (the calibration file's grid holds the
/// same in the board's: FileGridPoint).
struct ConditionSummary {
  double bias_kpa = 0, vacuum_kpa = 0;
  int cycles = 0;
  double stiffness_mean = 0, stiffness_spread = 0;  ///< N/mm (spread: standard deviation)
  double loop_area_mean = 0;                        ///< mJ
  double r2_min = 1;
};
/// The presses summarised per condition, in the order the conditions were first taken.
std::vector<ConditionSummary> SummariseConditions(const std::vector<MapPress>& presses);
/// As the calibration file's grid holds it: Pa and mN/mm.
host::GridPoint FileGridPoint(const ConditionSummary& c);

/// The bias with the least mean press loop area among those that keep at least 80 % of the
/// widest stiffness range (DESIGN §5: bias shrinks the loop; the range must stay).
double RecommendBias(const std::vector<ConditionSummary>& grid);

/// The bias recommended from a scattered map: over the lattice, the least mean press loop among
/// the biases keeping 80 % of the widest stiffness range (RecommendBias on fitted surfaces).
double RecommendBiasFromMap(const std::vector<MapPress>& presses, const MapBox& box);

/// Callbacks while a map is taken: a step's name, a finished step, every press.
struct MapHooks {
  std::function<void(const std::string&)> step;
  std::function<void()> done;
  std::function<void(const std::vector<MapPress>&)> after_press;
};

/// The condition from rest (vacuum released before, so every condition sees the same vacuum
/// history), the dwell, `repeats` presses, the vacuum released again.
RigStatus PressAt(Rig& rig, uint8_t finger, double zero_mm, double bias_kpa, double vacuum_kpa,
                  int repeats, const PressSettings& press, std::vector<MapPress>* out,
                  std::vector<PressCycle>* cycles = nullptr);

/// The thesis's grid: every bias × vacuum with `repeats` presses; a step per condition.
RigStatus RunGridMap(Rig& rig, uint8_t finger, double zero_mm, const PressSettings& press,
                     const std::vector<double>& biases_kpa, const std::vector<double>& vacuums_kpa,
                     int repeats, nlohmann::json& state, const MapHooks& hooks,
                     std::vector<MapPress>* presses, std::vector<PressCycle>* cycles = nullptr);

/// The adaptive protocol: a five-point start (corners and centre), then one press per step at
/// the most uncertain condition, one repeat of the worst-predicted condition once min_cycles are
/// in (the rig learns its press noise), until the target or the budget. *estimate says which.
RigStatus RunAdaptiveMap(Rig& rig, uint8_t finger, double zero_mm, const PressSettings& press,
                         const AdaptiveOptions& options, nlohmann::json& state,
                         const MapHooks& hooks, std::vector<MapPress>* presses,
                         MapEstimate* estimate, std::vector<PressCycle>* cycles = nullptr);

}  // namespace palpa::calibration
