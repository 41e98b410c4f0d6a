// Building a correction branch's bucket table (correction_lookup.h), once per configuration.
#include "palpa/core/correction_lookup.h"

#include <limits>

namespace palpa::core {

namespace {

void MakeBranch(const Correction& c, const float* produced, CorrectionBranch& b) {
  const uint8_t last = static_cast<uint8_t>(c.count - 1);
  for (uint8_t i = 0; i < c.count; ++i) b.point[i] = produced[i] * c.sign;
  b.point[c.count] = std::numeric_limits<float>::infinity();
  b.per_bucket = static_cast<float>(kCorrectionBuckets) / (b.point[last] - b.point[0]);
  // The inner points' buckets rise with the index (the bucket is monotone): each bucket starts
  // past the points of the buckets before it.
  uint8_t i = 1;
  for (uint32_t k = 0; k < kCorrectionBuckets; ++k) {
    while (i < last && CorrectionBucket(b, b.point[i]) < k) ++i;
    b.first[k] = i;
  }
}

}  // namespace

void MakeCorrection(const protocol::CorrectionPoint* points, uint8_t count, Correction& c) {
  c = Correction{};
  if (count < 2) return;
  c.count = count;
  float rising[protocol::kMaxCorrectionPoints], falling[protocol::kMaxCorrectionPoints];
  for (uint8_t i = 0; i < count; ++i) {
    c.command[i] = static_cast<float>(points[i].command_pa);
    rising[i] = static_cast<float>(points[i].rising_pa);
    falling[i] = static_cast<float>(points[i].falling_pa);
  }
  c.sign = rising[count - 1] > rising[0] ? 1.0f : -1.0f;
  MakeBranch(c, rising, c.rising);
  MakeBranch(c, falling, c.falling);
}

}  // namespace palpa::core
