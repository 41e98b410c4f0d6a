// Compensator parameter layouts: validation (what makes an inverse invalid) and table building.
//
//   pi:     [offset, w0, r_1..r_n, w_1..w_n]                    n = 1..32
//   api:    [n, offset, w0, r_1..r_n, w_1..w_n, d_1..d_m, g_1..g_m]  m = 1..8 dead zones
//   branch: [band, dead_band, y_1..y_K, rising_1..rising_K, falling_1..falling_K]  K = 2..24
#include "palpa/core/compensator.h"

namespace palpa::core {
namespace {

using protocol::CompensatorKind;

bool Finite(float v) { return __builtin_isfinite(v); }

/// Where the pieces of a play-operator parameter set sit in the params array.
struct PlayLayout {
  uint8_t n = 0;
  uint8_t m = 0;
  uint8_t offset = 0;  ///< index of the offset; w0 follows, then thresholds and weights
};

const char* ReadPlayLayout(const protocol::ConfigureFinger& f, PlayLayout& out) {
  const uint8_t count = f.param_count;
  if (f.compensator == CompensatorKind::kPrandtlIshlinskii) {
    if (count < 4 || count % 2 != 0)
      return "pi parameters: need offset, w0 and n thresholds and weights";
    out.n = static_cast<uint8_t>((count - 2) / 2);
    out.offset = 0;
  } else {
    if (count < 1) return "api parameters: missing the operator count";
    const float n = f.params[0];
    if (!(n >= 1 && n <= kMaxPlayOperators) || n != static_cast<float>(static_cast<int>(n))) {
      return "api parameters: operator count not an integer in 1..32";
    }
    out.n = static_cast<uint8_t>(n);
    const int rest = count - 3 - 2 * out.n;
    if (rest < 2 || rest % 2 != 0)
      return "api parameters: need n, offset, w0, n thresholds and weights, dead zones and gains";
    out.m = static_cast<uint8_t>(rest / 2);
    out.offset = 1;
  }
  if (out.n > kMaxPlayOperators) return "too many play operators (max 32)";
  if (out.m > kMaxDeadZones) return "too many dead zones (max 8)";
  return nullptr;
}

const char* PlayError(const protocol::ConfigureFinger& f) {
  PlayLayout l;
  if (const char* e = ReadPlayLayout(f, l)) return e;
  const float* p = f.params.data() + l.offset;
  const float w0 = p[1];
  const float* r = p + 2;
  const float* w = r + l.n;
  if (!(w0 > 0)) return "w0 must be positive (the inverse divides by it)";
  float cumulative = w0;
  for (uint8_t i = 0; i < l.n; ++i) {
    if (!Finite(r[i]) || r[i] < 0 || r[i] >= 100000) return "threshold not in 0..100 kPa";
    if (i > 0 && !(r[i] > r[i - 1])) return "thresholds not strictly increasing";
    cumulative += w[i];
    if (!(cumulative > 0)) return "cumulative weight not positive: the model is not invertible";
  }
  const float* d = w + l.n;
  const float* g = d + l.m;
  float slope = 1;
  for (uint8_t k = 0; k < l.m; ++k) {
    if (!Finite(d[k]) || d[k] < 0) return "dead-zone threshold negative or not finite";
    if (k > 0 && !(d[k] > d[k - 1])) return "dead-zone thresholds not strictly increasing";
    slope += g[k];
    if (!(slope > 0)) return "dead-zone slopes not positive: the output map is not invertible";
  }
  return nullptr;
}

bool StrictlyRising(const float* v, uint8_t n) {
  for (uint8_t i = 1; i < n; ++i) {
    if (!(v[i] > v[i - 1])) return false;
  }
  return true;
}

const char* BranchError(const protocol::ConfigureFinger& f) {
  const uint8_t count = f.param_count;
  if (count < 8 || (count - 2) % 3 != 0)
    return "branch parameters: need band, dead band and K outputs, rising and falling drives";
  const uint8_t k = static_cast<uint8_t>((count - 2) / 3);
  if (k > kMaxBranchPoints) return "too many branch points (max 24)";
  const float* p = f.params.data();
  if (!(p[0] > 0)) return "branch band must be positive";
  if (!(p[1] >= 0 && p[1] <= 5000)) return "branch dead band not in 0..5 kPa";
  const float* y = p + 2;
  const float* up = y + k;
  const float* down = up + k;
  for (uint8_t i = 0; i < k; ++i) {
    if (!(up[i] >= 0 && up[i] <= 100000) || !(down[i] >= 0 && down[i] <= 100000))
      return "branch drive not in 0..100 kPa";
  }
  if (!StrictlyRising(y, k)) return "branch outputs not strictly increasing";
  if (!StrictlyRising(up, k) || !StrictlyRising(down, k))
    return "branch drives not strictly increasing";
  return nullptr;
}

Compensator MakePlay(const protocol::ConfigureFinger& f, Compensator c) {
  PlayLayout l;
  ReadPlayLayout(f, l);
  const float* p = f.params.data() + l.offset;
  const float* r = p + 2;
  const float* w = r + l.n;
  PlayTable& t = c.play;
  t.operators = l.n;
  t.dead_zones = l.m;
  t.offset = p[0];
  t.w0_inverse = 1.0f / p[1];
  t.inverse_gain = t.w0_inverse;
  float before = p[1];  // W_{i-1}
  float weighted_thresholds = 0;
  for (uint8_t i = 0; i < l.n; ++i) {
    PlayOperator& op = t.op[i];
    op.threshold = r[i];
    op.weight = w[i];
    op.cumulative = before + w[i];
    weighted_thresholds += w[i] * r[i];
    op.inverse_threshold = op.cumulative * r[i] - weighted_thresholds;
    const float inverse_weight = -w[i] / (op.cumulative * before);
    op.half_inverse_weight = 0.5f * inverse_weight;
    t.inverse_gain += inverse_weight;
    before = op.cumulative;
  }
  // S(v) = v + Σ g_k max(v − d_k, 0): knots at d_k; S⁻¹ slope above knot k is 1 / (1 + Σ_{j≤k}
  // g_j).
  const float* d = w + l.n;
  const float* g = d + l.m;
  t.knot_in[0] = 0;
  t.knot_out[0] = 0;
  t.inverse_slope[0] = 1;
  float slope = 1;
  for (uint8_t k = 0; k < l.m; ++k) {
    const float in_prev = t.knot_in[k];
    t.knot_in[k + 1] = d[k];
    t.knot_out[k + 1] = t.knot_out[k] + (d[k] - in_prev) * slope;
    slope += g[k];
    t.inverse_slope[k + 1] = 1.0f / slope;
  }
  return c;
}

Compensator MakeBranch(const protocol::ConfigureFinger& f, Compensator c) {
  const uint8_t k = static_cast<uint8_t>((f.param_count - 2) / 3);
  BranchTable& t = c.branch;
  t = BranchTable{};
  t.points = k;
  t.band = f.params[0];
  t.dead_band = f.params[1];
  for (uint8_t i = 0; i < k; ++i) {
    t.output[i] = f.params[2 + i];
    t.rising[i] = f.params[2 + k + i];
    t.falling[i] = f.params[2 + 2 * k + i];
  }
  return c;
}

}  // namespace

const char* CompensatorParamsError(const protocol::ConfigureFinger& finger) {
  for (uint8_t i = 0; i < finger.param_count; ++i) {
    if (!Finite(finger.params[i])) return "compensator parameter is NaN or infinite";
  }
  switch (finger.compensator) {
    case CompensatorKind::kNone:
      return finger.param_count == 0 ? nullptr : "the none compensator takes no parameters";
    case CompensatorKind::kPrandtlIshlinskii:
    case CompensatorKind::kAsymmetricPi:
      return PlayError(finger);
    case CompensatorKind::kBranch:
      return BranchError(finger);
    default:
      return "unknown compensator";
  }
}

Compensator MakeCompensator(const protocol::ConfigureFinger& finger, float drive_limit) {
  Compensator c;
  c.kind = finger.compensator;
  c.drive_limit = drive_limit;
  switch (finger.compensator) {
    case CompensatorKind::kPrandtlIshlinskii:
    case CompensatorKind::kAsymmetricPi:
      return MakePlay(finger, c);
    case CompensatorKind::kBranch:
      return MakeBranch(finger, c);
    default:
      return c;
  }
}

}  // namespace palpa::core
