// Building a correction branch's bucket table (correction_lookup.h), once per configuration.
#include "palpa/core/correction_lookup.h"

#include <limits>

namespace palpa::core {

void MakeCorrectionBranch(const float* command, const float* produced, uint8_t count,
                          CorrectionBranch& b) {
  const uint8_t last = static_cast<uint8_t>(count - 1);
  b.sign = produced[last] > produced[0] ? 1.0f : -1.0f;
  for (uint8_t i = 0; i < count; ++i) b.point[i] = produced[i] * b.sign;
  b.point[count] = std::numeric_limits<float>::infinity();
  b.first_offset = command[0] - produced[0];
  b.last_offset = command[last] - produced[last];
  b.last_point = b.point[last];
  b.per_bucket = static_cast<float>(kCorrectionBuckets) / (b.point[last] - b.point[0]);
  // The inner points' buckets rise with the index (the bucket is monotone): each bucket starts
  // past the points of the buckets before it.
  uint8_t i = 1;
  for (uint32_t k = 0; k < kCorrectionBuckets; ++k) {
    while (i < last && CorrectionBucket(b, b.point[i]) < k) ++i;
    b.first[k] = i;
  }
}

}  // namespace palpa::core
