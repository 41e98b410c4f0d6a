// Compensator parameters: validation (what makes an inverse invalid) and table building. The
// layouts themselves are protocol/compensator_params.h's.
#include "palpa/protocol/compensator_params.h"
#include "palpa/core/compensator.h"
#include "play_lanes.h"

namespace palpa::core {
namespace {

using protocol::CompensatorKind;

bool Finite(float v) { return __builtin_isfinite(v); }

const char* ReadPlay(const protocol::ConfigureFinger& f, protocol::PlayParamSet& out) {
  return protocol::ReadPlayParams(f.compensator, f.params.data(), f.param_count, out);
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
  protocol::PlayParamSet set;
  if (const char* e = ReadPlay(f, set)) return e;
  const float w0 = set.w0;
  const float* r = set.thresholds;
  const float* w = set.weights;
  const uint8_t n = set.operators;
  if (!(w0 > 0)) return "w0 must be positive (the inverse divides by it)";
  float cumulative = w0;
  for (uint8_t i = 0; i < n; ++i) {
    if (!Finite(r[i]) || r[i] < 0 || r[i] >= 100000) return "threshold not in 0..100 kPa";
    if (i > 0 && !(r[i] > r[i - 1])) return "thresholds not strictly increasing";
    cumulative += w[i];
    if (!(cumulative > 0)) return "cumulative weight not positive: the model is not invertible";
  }
  PlayTable scratch;  // the tables the board would build, only to see that they are finite
  scratch.w0 = w0;
  if (!BuildPlayOperators(r, w, n, scratch))
    return "weights too far apart: the inverse overflows the board's arithmetic";
  const float* d = set.dead_zone_thresholds;
  const float* g = set.dead_zone_gains;
  float slope = 1;
  for (uint8_t k = 0; k < set.dead_zones; ++k) {
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
  protocol::BranchParamSet set;
  if (const char* e = protocol::ReadBranchParams(f.params.data(), f.param_count, set)) return e;
  const uint8_t k = set.points;
  if (!(set.band > 0)) return "branch band must be positive";
  if (!(set.dead_band >= 0 && set.dead_band <= 5000)) return "branch dead band not in 0..5 kPa";
  const float* y = set.outputs;
  const float* up = set.rising;
  const float* down = set.falling;
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
  protocol::PlayParamSet set;
  ReadPlay(f, set);  // validated by PlayError
  PlayTable& t = c.play;
  t.operators = set.operators;
  t.pairs = static_cast<uint8_t>((set.operators + 1) / 2);
  t.dead_zones = set.dead_zones;
  t.offset = set.offset;
  t.w0 = set.w0;
  (void)BuildPlayOperators(set.thresholds, set.weights, set.operators, t);
  // S(v) = v + Σ g_k max(v − d_k, 0): knots at d_k; S⁻¹ slope above knot k is 1 / (1 + Σ_{j≤k}
  // g_j).
  const float* d = set.dead_zone_thresholds;
  const float* g = set.dead_zone_gains;
  t.knot_in[0] = 0;
  t.knot_out[0] = 0;
  t.inverse_slope[0] = 1;
  float slope = 1;
  for (uint8_t k = 0; k < set.dead_zones; ++k) {
    const float in_prev = t.knot_in[k];
    t.knot_in[k + 1] = d[k];
    t.knot_out[k + 1] = t.knot_out[k] + (d[k] - in_prev) * slope;
    slope += g[k];
    t.inverse_slope[k + 1] = 1.0f / slope;
  }
  return c;
}

Compensator MakeBranch(const protocol::ConfigureFinger& f, Compensator c) {
  protocol::BranchParamSet set;
  protocol::ReadBranchParams(f.params.data(), f.param_count, set);  // validated by BranchError
  BranchTable& t = c.branch;
  t = BranchTable{};
  t.points = set.points;
  t.band = set.band;
  t.dead_band = set.dead_band;
  for (uint8_t i = 0; i < set.points; ++i) {
    t.output[i] = set.outputs[i];
    t.rising[i] = set.rising[i];
    t.falling[i] = set.falling[i];
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
