// A regulator correction's branch looked up in constant time: buckets over the produced pressure,
// built when the line is configured, in place of a search through the points every tick.
#pragma once

#include <array>
#include <cstdint>
#include <limits>

#include "palpa/core/internal/float_ops.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::core {

/// Buckets per branch: one per point the correction may have, so points spaced as calibration
/// spaces them (evenly in command, the produced pressure a few percent unevenly) lie at most one
/// to a bucket, and a lookup steps past at most one of them.
inline constexpr uint8_t kCorrectionBuckets = protocol::kMaxCorrectionPoints;

/// One branch of a regulator correction: what the regulator produced, its commands rising (or
/// falling), with what the lookup needs precomputed.
struct CorrectionBranch {
  /// An input's bucket: (input × sign − point[0]) × per_bucket, truncated, the last bucket at most.
  float per_bucket = 0;
  /// Per bucket, the first point that can lie beyond an input of the bucket (1 + the inner points
  /// in earlier buckets): the walk to the input's segment starts there.
  std::array<uint8_t, kCorrectionBuckets> first{};
  /// The produced pressures times the correction's sign, and past the last an infinity, which
  /// ends every walk.
  std::array<float, protocol::kMaxCorrectionPoints + 1> point{};
};

/// A line's regulator correction, both branches. The produced pressures are kept times `sign`, so
/// that they rise with the index on either kind of line (validation holds both branches to the
/// commands' direction): a negation is exact, and so is everything computed from it.
struct Correction {
  uint8_t count = 0;  ///< points; fewer than 2: none
  float sign = 1;     ///< +1 where the pressures rise with the index, else −1
  std::array<float, protocol::kMaxCorrectionPoints> command{};  ///< the points' commands
  CorrectionBranch rising{}, falling{};
};

/// The correction of a line's `count` points (validated: none, or at least 2 strictly monotone).
void MakeCorrection(const protocol::CorrectionPoint* points, uint8_t count, Correction& c);

/// An input's bucket (the input times the sign, at least the first point), the same function when
/// the table is built and when it is read: monotone in the input, so every inner point in an
/// earlier bucket lies before it. Truncated with saturation (one VCVT on the Cortex-M4F), then
/// held to the last bucket in integers: an input far beyond the points needs no float compare.
inline uint32_t CorrectionBucket(const CorrectionBranch& b, float signed_at) {
  constexpr int32_t kLastBucket = kCorrectionBuckets - 1;
  const int32_t k = TruncateSaturating((signed_at - b.point[0]) * b.per_bucket);  // 0 or more
  return static_cast<uint32_t>(k < kLastBucket ? k : kLastBucket);
}

/// The command that makes the regulator produce `at` on a branch: to the bit what Interpolate
/// over the points gives, the nearest end's offset held beyond them (a correction covers 10-90 %
/// of the range; the end's command itself would ask a 3 kPa target for what made 10 kPa). One
/// multiply, a table read and a step or two instead of a search.
inline float CorrectionCommand(const Correction& c, const CorrectionBranch& b, float at) {
  const float u = at * c.sign;
  const float* x = b.point.data();
  const float* y = c.command.data();
  // Below the points the first point's offset holds, command − produced there (the produced
  // pressure is the point times the sign, exactly; not kept: 16 bytes a line).
  if (u < x[0]) return at + (y[0] - x[0] * c.sign);
  // The first point beyond `u`, as Interpolate finds it: past the last one, the infinity. Walked
  // by pointer, the commands' pointer alongside (an index and a pointer both, otherwise).
  const uint32_t first = b.first[CorrectionBucket(b, u)];
  const float* px = x + first;
  const float* py = y + first;
  while (*px <= u) ++px, ++py;
  // Past the last point: the walk stopped on the infinity (the points are finite), which it has
  // just read, so no count is needed to tell.
  if (*px == std::numeric_limits<float>::infinity()) {
    // On the last point (Interpolate's last command) or beyond it (its offset).
    return u > px[-1] ? at + (py[-1] - px[-1] * c.sign) : py[-1];
  }
  // Interpolate's segment, its span never 0 here (the points are strictly monotone).
  return py[-1] + (u - px[-1]) / (px[0] - px[-1]) * (py[0] - py[-1]);
}

}  // namespace palpa::core
