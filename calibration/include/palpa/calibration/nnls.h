// Non-negative least squares (Lawson–Hanson active set) on small dense problems.
#pragma once

#include <string>
#include <vector>

namespace palpa::calibration {

/// Rows of a design matrix, all of the same length.
using Matrix = std::vector<std::vector<double>>;

struct NnlsResult {
  std::vector<double> x;  ///< the solution, every element ≥ 0
  double residual_rms = 0;
  int iterations = 0;
  bool converged = false;
};

/// min ‖A x − b‖ subject to x ≥ 0. Columns are scaled to unit norm internally, so regressors of
/// very different sizes (pascals and millimetres) do not spoil the conditioning.
NnlsResult SolveNnls(const Matrix& a, const std::vector<double>& b);

/// The same with a free intercept c (any sign): min ‖A x + c − b‖, x ≥ 0. Returns c in *intercept.
NnlsResult SolveNnlsWithIntercept(const Matrix& a, const std::vector<double>& b, double* intercept);

}  // namespace palpa::calibration
