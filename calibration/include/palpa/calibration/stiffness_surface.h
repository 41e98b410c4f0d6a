// The stiffness map of a jamming finger over its working box (bias × vacuum), fitted to scattered
// press results as a Gaussian process: a smooth surface with an uncertainty at every condition,
// and leave-one-condition-out cross-validation — what the adaptive protocol chooses with and stops
// on, and what both protocols are scored through.
#pragma once

#include <vector>

namespace palpa::calibration {

/// One press result at a condition (kPa; vacuum ≤ 0).
struct MapSample {
  double bias_kpa = 0;
  double vacuum_kpa = 0;
  double stiffness = 0;  ///< N/mm
};

/// The box the map covers; conditions are normalised to 0..1 inside it.
struct MapBox {
  double bias_max_kpa = 20;
  double vacuum_max_kpa = 100;  ///< magnitude
};

struct MapPrediction {
  double mean = 0;  ///< N/mm
  double sd = 0;    ///< of the surface (not of one press), N/mm
};

class StiffnessSurface {
 public:
  /// Fits the surface; the kernel's length scales and the noise are chosen by the marginal
  /// likelihood over a fixed grid. Needs at least two samples at different conditions.
  StiffnessSurface(const std::vector<MapSample>& samples, const MapBox& box);

  bool ok() const { return ok_; }
  MapPrediction Predict(double bias_kpa, double vacuum_kpa) const;

  /// Leave-one-condition-out: every condition's presses predicted from all the others; the RMS of
  /// the relative residuals (a fraction, e.g. 0.02). What a rig can know of its map's error.
  double CrossValidatedError() const { return cv_error_; }
  /// The noise of one press the fit settled on, relative to the mean stiffness.
  double PressNoise() const { return noise_ratio_ * signal_sd_ / mean_; }
  int conditions() const { return conditions_; }
  /// The sampled condition its neighbours predict worst (the largest cross-validation residual).
  MapSample WorstPredicted() const { return worst_; }

 private:
  double Kernel(double u1, double w1, double u2, double w2) const;
  double FitFor(double length_u, double length_w, double noise_ratio, bool keep);

  MapBox box_;
  std::vector<double> u_, w_, y_;
  bool ok_ = false;
  int conditions_ = 0;
  double mean_ = 0, signal_sd_ = 1, length_u_ = 1, length_w_ = 0.2, noise_ratio_ = 0.05;
  std::vector<double> alpha_;                 ///< K⁻¹ (y − mean)
  std::vector<std::vector<double>> inverse_;  ///< K⁻¹ (unit signal variance)
  double cv_error_ = 1;
  MapSample worst_{};
};

/// The next condition to press: the one, among the candidates, where the surface is least sure
/// of itself relative to its value (a sampled condition can win again: a repeat).
MapSample NextCondition(const StiffnessSurface& surface, const std::vector<MapSample>& candidates);

/// Candidate conditions on a regular lattice over the box (`bias_steps` × `vacuum_steps` points).
std::vector<MapSample> Lattice(const MapBox& box, int bias_steps, int vacuum_steps);

}  // namespace palpa::calibration
