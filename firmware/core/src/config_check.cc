// The live configuration's integrity check, a slice per tick.
#include "palpa/core/internal/config_check.h"

#include "palpa/protocol/crc32.h"

namespace palpa::core {
namespace {

constexpr uint32_t kCrcSliceBytes = 512;  // per tick: a 6 KB configuration every ~12 ticks

const uint8_t* Bytes(const BoardConfig& config) {
  return reinterpret_cast<const uint8_t*>(&config);
}

}  // namespace

void ConfigCheck::Restart(const BoardConfig& live, uint64_t now_us) {
  memory_crc_ = protocol::Crc32(Bytes(live), sizeof(live));
  offset_ = 0;
  pass_crc_ = 0;
  next_pass_us_ = now_us;
  intact_ = true;
}

bool ConfigCheck::Step(const BoardConfig& live, uint64_t now_us) {
  if (offset_ == 0) {  // a pass starts every check period and takes a few ticks
    if (now_us < next_pass_us_) return intact_;
    next_pass_us_ = now_us + static_cast<uint64_t>(live.board.config_check_period_ms) * 1000;
  }
  const uint32_t remaining = static_cast<uint32_t>(sizeof(live)) - offset_;
  const uint32_t slice = remaining < kCrcSliceBytes ? remaining : kCrcSliceBytes;
  pass_crc_ = protocol::Crc32Update(pass_crc_, Bytes(live) + offset_, slice);
  offset_ += slice;
  if (offset_ < sizeof(live)) return intact_;
  intact_ = pass_crc_ == memory_crc_;
  offset_ = 0;
  pass_crc_ = 0;
  return intact_;
}

}  // namespace palpa::core
