// Compensator parameter layouts: validation (what makes an inverse invalid) and table building.
//
//   pi:     [offset, w0, r_1..r_n, w_1..w_n]                    n = 1..32
//   api:    [n, offset, w0, r_1..r_n, w_1..w_n, d_1..d_m, g_1..g_m]  m = 1..8 dead zones
//   branch: [band, dead_band, y_1..y_K, rising_1..rising_K, falling_1..falling_K]  K = 2..24
#include "palpa/core/compensator.h"

#include "play_lanes.h"

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

/// Nearest integer; 0 for what no int32 holds (NaN, infinities), so a parameter set that
/// overflows is refused by BuildPlayOperators' result rather than converted undefined.
int32_t Round(float v) {
  if (!(v > -2.0e9f && v < 2.0e9f)) return 0;
  return static_cast<int32_t>(v + (v < 0 ? -0.5f : 0.5f));
}
float Largest(float a, float b) { return a > b ? a : b; }
float Magnitude(float v) { return v < 0 ? -v : v; }

/// The integer operator tables of PlayTable and their scales, chosen per parameter set so that
///  * thresholds take at most 14 bits (a drive change saturated at ±32767 steps still moves
///    every operator onto its clamp, as the true change would);
///  * every W_i and w_i fits int16;
///  * Σ_j |w_j| r_j + max_i |W_i| r_i ≤ 2²⁹ sum steps, which bounds every r'_i too
///    (r'_i = W_i r_i − Σ_{j≤i} w_j r_j): PlayStep's sums stay inside int32 (within 1.5 · 2³⁰)
///    from any start in ±2³⁰, and a start clamped there still leaves every state on its clamp;
///  * every w'_i fits int16 and Σ |w'_i| r'_i fits the drive accumulator with room (2³⁰).
/// False when a scale or an inverse constant is not a finite float (weights so far apart that
/// the inverse overflows): validation refuses such a set.
bool BuildPlayOperators(const float* r, const float* w, uint8_t n, PlayTable& t) {
  constexpr float kTwo16 = 65536.0f;
  float cumulative[kMaxPlayOperators];
  float inverse_threshold[kMaxPlayOperators];
  float inverse_weight[kMaxPlayOperators];
  float before = t.w0;  // W_{i-1}
  float weighted_thresholds = 0;
  float largest_weight = 0;
  float weighted_spread = 0;  // Σ |w_j| r_j
  float widest = 0;           // max |W_i| r_i
  t.inverse_gain = 1.0f / t.w0;
  bool finite = true;
  for (uint8_t i = 0; i < n; ++i) {
    cumulative[i] = before + w[i];
    weighted_thresholds += w[i] * r[i];
    inverse_threshold[i] = cumulative[i] * r[i] - weighted_thresholds;
    inverse_weight[i] = -w[i] / (cumulative[i] * before);
    t.inverse_gain += inverse_weight[i];
    largest_weight = Largest(largest_weight, Largest(cumulative[i], Magnitude(w[i])));
    weighted_spread += Magnitude(w[i]) * r[i];
    widest = Largest(widest, cumulative[i] * r[i]);
    finite = finite && Finite(inverse_threshold[i]) && Finite(inverse_weight[i]);
    before = cumulative[i];
  }
  t.drive_step = Largest(r[n - 1] / 16383.0f, 0.01f);
  t.per_drive_step = 1.0f / t.drive_step;
  t.sum_step =
      Largest(largest_weight * t.drive_step / 32767.0f, (weighted_spread + widest) / 536870912.0f);
  t.per_sum_step = 1.0f / t.sum_step;
  const float weight_scale = t.drive_step * t.per_sum_step;  // sum steps per drive step
  t.applied_gain = before * weight_scale;
  int32_t state_bound[kMaxPlayOperators];
  float largest_inverse_weight = 0;
  float inverse_spread = 0;
  for (uint8_t i = 0; i < n; ++i) {
    state_bound[i] = Round(Magnitude(inverse_threshold[i]) * t.per_sum_step / kTwo16);
    largest_inverse_weight = Largest(largest_inverse_weight, Magnitude(inverse_weight[i]));
    inverse_spread += Magnitude(inverse_weight[i]) * static_cast<float>(state_bound[i]);
  }
  const float inverse_weight_step =
      Largest(Largest(largest_inverse_weight / 32767.0f, inverse_spread / 1073741824.0f), 1e-30f);
  t.drive_gain = inverse_weight_step * kTwo16 * t.sum_step;
  for (uint8_t k = 0; k < (n + 1) / 2; ++k) {
    int32_t lane[2][5] = {};  // r, W, w, r', w' of operators 2k and 2k+1 (zero: a padding one)
    for (uint8_t j = 0; j < 2 && 2 * k + j < n; ++j) {
      const uint8_t i = static_cast<uint8_t>(2 * k + j);
      lane[j][0] = Round(r[i] * t.per_drive_step);
      lane[j][1] = Round(cumulative[i] * weight_scale);
      lane[j][2] = Round(w[i] * weight_scale);
      lane[j][3] = state_bound[i];
      lane[j][4] = Round(inverse_weight[i] / inverse_weight_step);
    }
    PlayPair& pair = t.pair[k];
    pair.threshold = lanes::Pack(lane[0][0], lane[1][0]);
    pair.negative_threshold = lanes::Pack(-lane[0][0], -lane[1][0]);
    pair.cumulative = lanes::Pack(lane[0][1], lane[1][1]);
    pair.mixed = lanes::Pack(lane[0][1], lane[1][2]);
    pair.weight = lanes::Pack(lane[0][2], lane[1][2]);
    pair.inverse_threshold = lanes::Pack(lane[0][3], lane[1][3]);
    pair.negative_inverse_threshold = lanes::Pack(-lane[0][3], -lane[1][3]);
    pair.inverse_weight = lanes::Pack(lane[0][4], lane[1][4]);
  }
  return finite && Finite(t.inverse_gain) && Finite(t.applied_gain) && t.sum_step > 0 &&
         Finite(t.per_sum_step) && t.drive_gain > 0 && Finite(t.drive_gain);
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
  PlayTable scratch;  // the tables the board would build, only to see that they are finite
  scratch.w0 = w0;
  if (!BuildPlayOperators(r, w, l.n, scratch))
    return "weights too far apart: the inverse overflows the board's arithmetic";
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
  t.pairs = static_cast<uint8_t>((l.n + 1) / 2);
  t.dead_zones = l.m;
  t.offset = p[0];
  t.w0 = p[1];
  (void)BuildPlayOperators(r, w, l.n, t);  // validated by PlayError
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
