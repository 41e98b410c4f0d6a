// A regulator correction's branch looked up in constant time: buckets over the produced pressure,
// built when the line is configured, in place of a search through the points every tick.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/messages_config.h"

namespace palpa::core {

/// Buckets per branch: two per point, so points spaced as calibration spaces them (evenly in
/// command, the produced pressure a little unevenly) lie at most one to a bucket, and a lookup
/// steps past at most one of them.
inline constexpr uint8_t kCorrectionBuckets = 2 * protocol::kMaxCorrectionPoints;

/// One branch of a regulator correction: what the regulator produced, its commands rising (or
/// falling), with what the lookup needs precomputed. The produced pressures are kept times
/// `sign`, so that they rise with the index on either branch of either kind of line: a negation
/// is exact, and so is everything computed from the negated values.
struct CorrectionBranch {
  float sign = 1;  ///< +1 where the produced pressure rises with the index, else −1
  /// Beyond the points the nearest end's offset holds: command − produced at the first point and
  /// at the last.
  float first_offset = 0, last_offset = 0;
  float last_point = 0;  ///< the last point's produced pressure times `sign`
  /// An input's bucket: (input × sign − point[0]) × per_bucket, truncated, the last bucket at most.
  float per_bucket = 0;
  /// Per bucket, the first point that can lie beyond an input of the bucket (1 + the inner points
  /// in earlier buckets): the walk to the input's segment starts there.
  std::array<uint8_t, kCorrectionBuckets> first{};
  /// The produced pressures times `sign`, and past the last an infinity, which ends every walk.
  std::array<float, protocol::kMaxCorrectionPoints + 1> point{};
};

/// The branch over `count` (≥ 2) points strictly monotone in `produced`; `command` the commands
/// that produced them.
void MakeCorrectionBranch(const float* command, const float* produced, uint8_t count,
                          CorrectionBranch& branch);

/// An input's bucket (the input times `sign`), the same function when the table is built and when
/// it is read: monotone in the input, so every inner point in an earlier bucket lies before it.
inline uint32_t CorrectionBucket(const CorrectionBranch& b, float signed_at) {
  constexpr uint32_t kLastBucket = kCorrectionBuckets - 1;
  const float f = (signed_at - b.point[0]) * b.per_bucket;
  return f < static_cast<float>(kLastBucket) ? static_cast<uint32_t>(f) : kLastBucket;
}

/// The command that makes the regulator produce `at` on this branch: to the bit what Interpolate
/// over the points gives, the nearest end's offset held beyond them (a correction covers 10-90 %
/// of the range; the end's command itself would ask a 3 kPa target for what made 10 kPa).
/// `command` holds the correction's commands and one more, finite, past the last. One multiply,
/// a table read and a step or two instead of a search.
inline float CorrectionCommand(const CorrectionBranch& b, const float* command, float at) {
  const float u = at * b.sign;
  if (u < b.point[0]) return at + b.first_offset;
  if (u > b.last_point) return at + b.last_offset;
  // The first point beyond `u`, as Interpolate finds it (on the last point: past it, the
  // infinity, whose segment gives the last command exactly, as Interpolate returns it).
  const float* x = b.point.data();
  uint32_t i = b.first[CorrectionBucket(b, u)];
  while (x[i] <= u) ++i;
  // Interpolate's segment, its span never 0 here (the points are strictly monotone).
  return command[i - 1] + (u - x[i - 1]) / (x[i] - x[i - 1]) * (command[i] - command[i - 1]);
}

}  // namespace palpa::core
