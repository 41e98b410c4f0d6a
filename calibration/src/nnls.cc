// Lawson–Hanson NNLS on the normal equations (the problems here have at most a few dozen columns).
#include "palpa/calibration/nnls.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace palpa::calibration {
namespace {

/// Solves the symmetric positive (semi)definite system restricted to `set` by Cholesky; columns
/// that turn out dependent get 0.
std::vector<double> SolveSubset(const Matrix& ata, const std::vector<double>& atb,
                                const std::vector<int>& set) {
  const size_t k = set.size();
  std::vector<double> l(k * k, 0), y(k, 0), x(k, 0);
  std::vector<bool> dead(k, false);
  for (size_t i = 0; i < k; ++i) {
    for (size_t j = 0; j <= i; ++j) {
      double s = ata[set[i]][set[j]];
      for (size_t p = 0; p < j; ++p) s -= l[i * k + p] * l[j * k + p];
      if (i == j) {
        if (s <= 1e-12 * ata[set[i]][set[i]] || s <= 0) {
          dead[i] = true;
          l[i * k + i] = 1;
        } else {
          l[i * k + i] = std::sqrt(s);
        }
      } else {
        l[i * k + j] = dead[j] ? 0 : s / l[j * k + j];
      }
    }
    if (dead[i]) {
      for (size_t p = 0; p < i; ++p) l[i * k + p] = 0;
    }
  }
  for (size_t i = 0; i < k; ++i) {
    double s = atb[set[i]];
    for (size_t p = 0; p < i; ++p) s -= l[i * k + p] * y[p];
    y[i] = dead[i] ? 0 : s / l[i * k + i];
  }
  for (size_t i = k; i-- > 0;) {
    double s = y[i];
    for (size_t p = i + 1; p < k; ++p) s -= l[p * k + i] * x[p];
    x[i] = dead[i] ? 0 : s / l[i * k + i];
  }
  return x;
}

}  // namespace

NnlsResult SolveNnls(const Matrix& a, const std::vector<double>& b) {
  NnlsResult r;
  if (a.empty()) return r;
  const size_t rows = a.size(), cols = a[0].size();
  std::vector<double> scale(cols, 0);
  for (const auto& row : a) {
    for (size_t j = 0; j < cols; ++j) scale[j] += row[j] * row[j];
  }
  for (double& s : scale) s = s > 0 ? 1.0 / std::sqrt(s) : 0.0;
  Matrix ata(cols, std::vector<double>(cols, 0));
  std::vector<double> atb(cols, 0);
  for (size_t i = 0; i < rows; ++i) {
    for (size_t j = 0; j < cols; ++j) {
      const double aj = a[i][j] * scale[j];
      atb[j] += aj * b[i];
      for (size_t k = 0; k <= j; ++k) ata[j][k] += aj * a[i][k] * scale[k];
    }
  }
  for (size_t j = 0; j < cols; ++j) {
    for (size_t k = j + 1; k < cols; ++k) ata[j][k] = ata[k][j];
  }
  std::vector<double> x(cols, 0);
  std::vector<bool> passive(cols, false);
  const double tolerance =
      1e-10 * (1.0 + *std::max_element(atb.begin(), atb.end(), [](double p, double q) {
                 return std::fabs(p) < std::fabs(q);
               }));
  const int max_iterations = static_cast<int>(3 * cols + 30);
  auto gradient = [&](size_t j) {
    double g = atb[j];
    for (size_t k = 0; k < cols; ++k) g -= ata[j][k] * x[k];
    return g;
  };
  for (r.iterations = 0; r.iterations < max_iterations; ++r.iterations) {
    int best = -1;
    double best_g = tolerance;
    for (size_t j = 0; j < cols; ++j) {
      if (passive[j] || scale[j] == 0) continue;
      const double g = gradient(j);
      if (g > best_g) {
        best_g = g;
        best = static_cast<int>(j);
      }
    }
    if (best < 0) {
      r.converged = true;
      break;
    }
    passive[best] = true;
    for (int inner = 0; inner < max_iterations; ++inner) {
      std::vector<int> set;
      for (size_t j = 0; j < cols; ++j) {
        if (passive[j]) set.push_back(static_cast<int>(j));
      }
      const std::vector<double> z = SolveSubset(ata, atb, set);
      bool feasible = true;
      for (double v : z) feasible = feasible && v > 0;
      if (feasible) {
        for (size_t i = 0; i < set.size(); ++i) x[set[i]] = z[i];
        break;
      }
      // Step toward z only as far as keeps every variable ≥ 0, then drop those that hit 0.
      double alpha = std::numeric_limits<double>::max();
      for (size_t i = 0; i < set.size(); ++i) {
        if (z[i] <= 0) alpha = std::min(alpha, x[set[i]] / (x[set[i]] - z[i]));
      }
      for (size_t i = 0; i < set.size(); ++i) {
        x[set[i]] += alpha * (z[i] - x[set[i]]);
        if (x[set[i]] <= 1e-15) {
          x[set[i]] = 0;
          passive[set[i]] = false;
        }
      }
    }
  }
  double sum = 0;
  for (size_t i = 0; i < rows; ++i) {
    double fit = 0;
    for (size_t j = 0; j < cols; ++j) fit += a[i][j] * scale[j] * x[j];
    sum += (fit - b[i]) * (fit - b[i]);
  }
  r.residual_rms = std::sqrt(sum / static_cast<double>(rows));
  r.x.resize(cols);
  for (size_t j = 0; j < cols; ++j) r.x[j] = x[j] * scale[j];
  return r;
}

NnlsResult SolveNnlsWithIntercept(const Matrix& a, const std::vector<double>& b,
                                  double* intercept) {
  // A free intercept is the least-squares problem on centred data; c follows from the means.
  const size_t rows = a.size(), cols = rows > 0 ? a[0].size() : 0;
  std::vector<double> mean(cols, 0);
  double mean_b = 0;
  for (size_t i = 0; i < rows; ++i) {
    for (size_t j = 0; j < cols; ++j) mean[j] += a[i][j] / static_cast<double>(rows);
    mean_b += b[i] / static_cast<double>(rows);
  }
  Matrix centred(rows, std::vector<double>(cols));
  std::vector<double> cb(rows);
  for (size_t i = 0; i < rows; ++i) {
    for (size_t j = 0; j < cols; ++j) centred[i][j] = a[i][j] - mean[j];
    cb[i] = b[i] - mean_b;
  }
  NnlsResult r = SolveNnls(centred, cb);
  double c = mean_b;
  for (size_t j = 0; j < cols; ++j) c -= mean[j] * r.x[j];
  if (intercept != nullptr) *intercept = c;
  return r;
}

}  // namespace palpa::calibration
