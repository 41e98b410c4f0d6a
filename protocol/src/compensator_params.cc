// Compensator parameter layouts: reading a set's shape and writing one (see the header).
#include "palpa/protocol/compensator_params.h"

namespace palpa::protocol {
namespace {

float* Copy(const float* from, size_t n, float* to) {
  for (size_t i = 0; i < n; ++i) *to++ = from[i];
  return to;
}

}  // namespace

const char* ReadPlayParams(CompensatorKind kind, const float* params, size_t count,
                           PlayParamSet& out) {
  size_t at = 0;
  if (kind == CompensatorKind::kPrandtlIshlinskii) {
    if (count < 4 || count % 2 != 0)
      return "pi parameters: need offset, w0 and n thresholds and weights";
    out.operators = static_cast<uint8_t>((count - 2) / 2);
    out.dead_zones = 0;
  } else {
    if (count < 1) return "api parameters: missing the operator count";
    const float n = params[0];
    if (!(n >= 1 && n <= kMaxPlayOperators) || n != static_cast<float>(static_cast<int>(n))) {
      return "api parameters: operator count not an integer in 1..32";
    }
    out.operators = static_cast<uint8_t>(n);
    const int rest = static_cast<int>(count) - 3 - 2 * out.operators;
    if (rest < 2 || rest % 2 != 0)
      return "api parameters: need n, offset, w0, n thresholds and weights, dead zones and gains";
    out.dead_zones = static_cast<uint8_t>(rest / 2);
    at = 1;
  }
  if (out.operators > kMaxPlayOperators) return "too many play operators (max 32)";
  if (out.dead_zones > kMaxDeadZones) return "too many dead zones (max 8)";
  out.offset = params[at];
  out.w0 = params[at + 1];
  out.thresholds = params + at + 2;
  out.weights = out.thresholds + out.operators;
  out.dead_zone_thresholds = out.weights + out.operators;
  out.dead_zone_gains = out.dead_zone_thresholds + out.dead_zones;
  return nullptr;
}

const char* ReadBranchParams(const float* params, size_t count, BranchParamSet& out) {
  if (count < BranchParamCount(2) || (count - 2) % 3 != 0)
    return "branch parameters: need band, dead band and K outputs, rising and falling drives";
  out.points = static_cast<uint8_t>((count - 2) / 3);
  if (out.points > kMaxBranchPoints) return "too many branch points (max 24)";
  out.band = params[0];
  out.dead_band = params[1];
  out.outputs = params + 2;
  out.rising = out.outputs + out.points;
  out.falling = out.rising + out.points;
  return nullptr;
}

size_t WritePlayParams(CompensatorKind kind, const PlayParamSet& set, float* out, size_t capacity) {
  const bool api = kind == CompensatorKind::kAsymmetricPi;
  const size_t count = PlayParamCount(kind, set.operators, set.dead_zones);
  if (count > capacity) return 0;
  float* at = out;
  if (api) *at++ = static_cast<float>(set.operators);
  *at++ = set.offset;
  *at++ = set.w0;
  at = Copy(set.thresholds, set.operators, at);
  at = Copy(set.weights, set.operators, at);
  if (api) {
    at = Copy(set.dead_zone_thresholds, set.dead_zones, at);
    Copy(set.dead_zone_gains, set.dead_zones, at);
  }
  return count;
}

size_t WriteBranchParams(const BranchParamSet& set, float* out, size_t capacity) {
  const size_t count = BranchParamCount(set.points);
  if (count > capacity) return 0;
  out[0] = set.band;
  out[1] = set.dead_band;
  Copy(set.falling, set.points,
       Copy(set.rising, set.points, Copy(set.outputs, set.points, out + 2)));
  return count;
}

}  // namespace palpa::protocol
