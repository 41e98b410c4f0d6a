// Gaussian-process stiffness surface: squared-exponential kernel with a length scale per axis,
// profiled signal variance, grid search over length scales and noise, closed-form block
// cross-validation.
#include "palpa/calibration/stiffness_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace palpa::calibration {
namespace {

using Matrix = std::vector<std::vector<double>>;

/// Lower Cholesky factor in place; false when the matrix is not positive definite.
bool Cholesky(Matrix& a) {
  const size_t n = a.size();
  for (size_t j = 0; j < n; ++j) {
    double d = a[j][j];
    for (size_t k = 0; k < j; ++k) d -= a[j][k] * a[j][k];
    if (d <= 0) return false;
    a[j][j] = std::sqrt(d);
    for (size_t i = j + 1; i < n; ++i) {
      double s = a[i][j];
      for (size_t k = 0; k < j; ++k) s -= a[i][k] * a[j][k];
      a[i][j] = s / a[j][j];
    }
  }
  return true;
}

/// Solves L Lᵀ x = b with the factor from Cholesky().
std::vector<double> CholeskySolve(const Matrix& l, std::vector<double> b) {
  const size_t n = l.size();
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < i; ++k) b[i] -= l[i][k] * b[k];
    b[i] /= l[i][i];
  }
  for (size_t i = n; i-- > 0;) {
    for (size_t k = i + 1; k < n; ++k) b[i] -= l[k][i] * b[k];
    b[i] /= l[i][i];
  }
  return b;
}

/// Solves a small dense system by Gaussian elimination with partial pivoting.
std::vector<double> SolveSmall(Matrix a, std::vector<double> b) {
  const size_t n = a.size();
  for (size_t c = 0; c < n; ++c) {
    size_t pivot = c;
    for (size_t r = c + 1; r < n; ++r) {
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    }
    std::swap(a[c], a[pivot]);
    std::swap(b[c], b[pivot]);
    for (size_t r = c + 1; r < n; ++r) {
      const double f = a[r][c] / a[c][c];
      for (size_t k = c; k < n; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (size_t r = n; r-- > 0;) {
    for (size_t k = r + 1; k < n; ++k) b[r] -= a[r][k] * b[k];
    b[r] /= a[r][r];
  }
  return b;
}

// Length scales in the normalised box, and press noise relative to the surface's spread: wide
// enough for a map that is nearly flat along bias and one that jumps within a tenth of the
// vacuum range (a finger without bias jams abruptly, DESIGN §5).
constexpr double kLengthsU[] = {0.25, 0.5, 1.0, 2.0};
constexpr double kLengthsW[] = {0.05, 0.08, 0.12, 0.18, 0.27, 0.4, 0.6};
constexpr double kNoiseRatios[] = {0.005, 0.02, 0.05, 0.15};

}  // namespace

StiffnessSurface::StiffnessSurface(const std::vector<MapSample>& samples, const MapBox& box)
    : box_(box) {
  std::map<std::pair<double, double>, int> seen;
  for (const MapSample& s : samples) {
    if (!std::isfinite(s.stiffness) || !std::isfinite(s.bias_kpa) || !std::isfinite(s.vacuum_kpa)) {
      continue;
    }
    u_.push_back(s.bias_kpa / box.bias_max_kpa);
    w_.push_back(-s.vacuum_kpa / box.vacuum_max_kpa);
    y_.push_back(s.stiffness);
    seen[{s.bias_kpa, s.vacuum_kpa}]++;
  }
  conditions_ = static_cast<int>(seen.size());
  for (double y : y_) mean_ += y / static_cast<double>(y_.size());
  if (conditions_ < 2) return;  // not a surface: predictions are the mean, as unsure as it is
  // No length scale below the typical spacing of the samples along its axis: between samples
  // that far apart the data cannot tell a short scale from a long one, and a short one would let
  // the surface sag back to its mean between them (a 3 × 3 grid would become three bumps).
  auto shortest = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    std::vector<double> gaps;
    for (size_t i = 1; i < v.size(); ++i) gaps.push_back(v[i] - v[i - 1]);
    if (gaps.empty()) return 0.0;
    std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
    return gaps[gaps.size() / 2];
  };
  const double min_u = shortest(u_), min_w = shortest(w_);
  double best = -std::numeric_limits<double>::infinity();
  double bu = 2, bw = 0.6, bn = 0.05;
  for (double lu : kLengthsU) {
    if (lu < min_u) continue;
    for (double lw : kLengthsW) {
      if (lw < min_w) continue;
      for (double r : kNoiseRatios) {
        const double l = FitFor(lu, lw, r, false);
        if (l > best) {
          best = l;
          bu = lu;
          bw = lw;
          bn = r;
        }
      }
    }
  }
  ok_ = std::isfinite(FitFor(bu, bw, bn, true));
}

double StiffnessSurface::Kernel(double u1, double w1, double u2, double w2) const {
  const double du = (u1 - u2) / length_u_, dw = (w1 - w2) / length_w_;
  return std::exp(-0.5 * (du * du + dw * dw));
}

double StiffnessSurface::FitFor(double length_u, double length_w, double noise_ratio, bool keep) {
  length_u_ = length_u;
  length_w_ = length_w;
  noise_ratio_ = noise_ratio;
  const size_t n = y_.size();
  Matrix k(n, std::vector<double>(n));
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) k[i][j] = Kernel(u_[i], w_[i], u_[j], w_[j]);
    k[i][i] += noise_ratio * noise_ratio;
  }
  Matrix l = k;
  if (!Cholesky(l)) return -std::numeric_limits<double>::infinity();
  std::vector<double> centred(n);
  for (size_t i = 0; i < n; ++i) centred[i] = y_[i] - mean_;
  const std::vector<double> a = CholeskySolve(l, centred);
  double quad = 0, log_det = 0;
  for (size_t i = 0; i < n; ++i) {
    quad += centred[i] * a[i];
    log_det += 2 * std::log(l[i][i]);
  }
  const double variance = std::max(quad / static_cast<double>(n), 1e-12);
  const double log_likelihood = -0.5 * static_cast<double>(n) * std::log(variance) - 0.5 * log_det;
  if (!keep) return log_likelihood;

  signal_sd_ = std::sqrt(variance);
  alpha_ = a;
  inverse_.assign(n, std::vector<double>(n));
  for (size_t j = 0; j < n; ++j) {
    std::vector<double> e(n, 0.0);
    e[j] = 1;
    const std::vector<double> column = CholeskySolve(l, e);
    for (size_t i = 0; i < n; ++i) inverse_[i][j] = column[i];
  }
  // Leave one condition out: r_B = [K⁻¹]_BB⁻¹ (K⁻¹ y)_B is y_B minus its prediction from the rest.
  std::map<std::pair<double, double>, std::vector<size_t>> groups;
  for (size_t i = 0; i < n; ++i) groups[{u_[i], w_[i]}].push_back(i);
  double sum = 0, worst = -1;
  for (const auto& [at, members] : groups) {
    Matrix block(members.size(), std::vector<double>(members.size()));
    std::vector<double> rhs(members.size());
    for (size_t p = 0; p < members.size(); ++p) {
      for (size_t q = 0; q < members.size(); ++q) block[p][q] = inverse_[members[p]][members[q]];
      rhs[p] = alpha_[members[p]];
    }
    const std::vector<double> residual = SolveSmall(block, rhs);
    for (size_t p = 0; p < members.size(); ++p) {
      const double relative = residual[p] / y_[members[p]];
      sum += relative * relative;
      if (std::fabs(relative) > worst) {
        worst = std::fabs(relative);
        worst_ = {at.first * box_.bias_max_kpa, -at.second * box_.vacuum_max_kpa, y_[members[p]]};
      }
    }
  }
  cv_error_ = std::sqrt(sum / static_cast<double>(n));
  return log_likelihood;
}

MapPrediction StiffnessSurface::Predict(double bias_kpa, double vacuum_kpa) const {
  if (!ok_) return {mean_, mean_};
  const double u = bias_kpa / box_.bias_max_kpa, w = -vacuum_kpa / box_.vacuum_max_kpa;
  const size_t n = y_.size();
  std::vector<double> k(n);
  for (size_t i = 0; i < n; ++i) k[i] = Kernel(u, w, u_[i], w_[i]);
  // Solved with unit signal variance: the mean is k̃ᵀ K̃⁻¹ ỹ, the variance σ²(1 − k̃ᵀ K̃⁻¹ k̃).
  double mean = mean_, reduction = 0;
  for (size_t i = 0; i < n; ++i) {
    mean += k[i] * alpha_[i];
    double row = 0;
    for (size_t j = 0; j < n; ++j) row += inverse_[i][j] * k[j];
    reduction += k[i] * row;
  }
  return {mean, signal_sd_ * std::sqrt(std::max(0.0, 1.0 - reduction))};
}

MapSample NextCondition(const StiffnessSurface& surface, const std::vector<MapSample>& candidates) {
  MapSample best = candidates.empty() ? MapSample{} : candidates.front();
  double most = -1;
  for (const MapSample& c : candidates) {
    const MapPrediction p = surface.Predict(c.bias_kpa, c.vacuum_kpa);
    const double relative = p.sd / std::max(std::fabs(p.mean), 1e-9);
    if (relative > most) {
      most = relative;
      best = c;
    }
  }
  return best;
}

std::vector<MapSample> Lattice(const MapBox& box, int bias_steps, int vacuum_steps) {
  std::vector<MapSample> out;
  for (int i = 0; i < bias_steps; ++i) {
    for (int j = 0; j < vacuum_steps; ++j) {
      const double b = bias_steps > 1 ? box.bias_max_kpa * i / (bias_steps - 1) : 0;
      const double v = vacuum_steps > 1 ? -box.vacuum_max_kpa * j / (vacuum_steps - 1) : 0;
      out.push_back({b, v, 0});
    }
  }
  return out;
}

}  // namespace palpa::calibration
