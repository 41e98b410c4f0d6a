// The benchmark images' side of the board shell (PALPA_BENCH): an in-image host that drives a
// session, and the compiled-in configuration with PI(16), shaped steps and corrections.
#pragma once

#include <cstdint>

#include "palpa/core/board.h"
#include "palpa/hal/mps2/drivers.h"
#include "palpa/protocol/codec.h"
#include "semihosting.h"

namespace palpa::boards::mps2 {
// Internal linkage, as when this was written into main.cc (its one includer): the same inlining.
namespace {

/// The in-image host: a session, every finger following a target, heartbeats every 20 ms;
/// 3 000 ticks whatever the start-up took, then exit. `Shell` gives the shell's uart, board and
/// clock through static functions, which the loop compiles as the shell's globals: kept in the
/// host instead, they cost the loop registers and moved the benchmark's figures.
template <class Shell>
class BenchHost {
 public:
  explicit BenchHost(const core::BoardConfig& config) {
    Inject(protocol::Hello{kSession, 0});
    protocol::SetFingerTargets targets{};
    targets.session = kSession;
    targets.generation = 1;
    for (uint8_t f = 0; f < config.finger_count; ++f) {
      const bool jamming = config.fingers[f].kind == protocol::FingerKind::kJamming;
      targets.entries[targets.entry_count++] = {
          f,
          jamming ? protocol::OutputUnit::kStiffnessMilliNewtonPerMm
                  : protocol::OutputUnit::kDeformationMicrometre,
          jamming ? 1000 : 1500};
    }
    Inject(targets);
    next_heartbeat_us_ = Shell::Clock().NowMicros() + 20000;
#ifdef PALPA_BENCH_SHAPED
    targets_ = targets;
    for (uint8_t i = 0; i < targets.entry_count; ++i) first_[i] = targets.entries[i].target;
#endif
  }
  void Heartbeat(uint64_t now_us) {
    if (now_us < next_heartbeat_us_) return;
    Inject(protocol::Heartbeat{kSession, ++heartbeat_});
    next_heartbeat_us_ += 20000;
  }
  void Ticked() {
    if (++ticks_ == 3000) SemihostExit(Shell::Board().safe() ? 1 : 0);
#ifdef PALPA_BENCH_SHAPED
    if (ticks_ % 40 == 0) {  // a new target for every finger: a shaped step on every line
      for (uint8_t i = 0; i < targets_.entry_count; ++i) {
        targets_.entries[i].target = ticks_ % 80 == 0 ? first_[i] : first_[i] + first_[i] / 4;
      }
      targets_.generation++;
      Inject(targets_);
    }
#endif
  }

 private:
  static constexpr uint32_t kSession = 1;  // the Hello's nonce, which every stream frame names
  template <class M>
  static void Inject(const M& message) {
    uint8_t frame[protocol::kMaxFrameSize];
    const auto n = protocol::EncodeMessageFrame(message, 0, 0, frame, sizeof(frame));
    Shell::Uart().Inject(frame, n.value);
  }
  uint32_t heartbeat_ = 0;
  uint64_t next_heartbeat_us_ = 0;
  uint32_t ticks_ = 0;
#ifdef PALPA_BENCH_SHAPED
  protocol::SetFingerTargets targets_{};
  int32_t first_[protocol::kMaxFingers] = {};
#endif
};

#ifdef PALPA_BENCH_PI16
core::BoardConfig g_pi16_config;

/// The compiled-in configuration with a PI(16) compensator on every finger (thresholds over half
/// the drive range, positive weights): what the whole-tick goal is measured with.
const core::BoardConfig* WithPi16OnEveryFinger(const core::BoardConfig& base) {
  g_pi16_config = base;
  for (uint8_t f = 0; f < g_pi16_config.finger_count; ++f) {
    protocol::ConfigureFinger& finger = g_pi16_config.fingers[f];
    const bool jamming = finger.kind == protocol::FingerKind::kJamming;
    finger.compensator = protocol::CompensatorKind::kPrandtlIshlinskii;
    finger.param_count = 34;
    finger.params[0] = jamming ? 700.0f : -200.0f;  // output at 0 Pa (mN/mm, or um)
    finger.params[1] = jamming ? 0.004f : 0.03f;
    for (int i = 0; i < 16; ++i) {
      finger.params[2 + i] = 50000.0f * static_cast<float>(i) / 16.0f;
      finger.params[18 + i] = jamming ? 0.0002f : 0.001f;
    }
  }
#ifdef PALPA_BENCH_SHAPED
  // Shaped steps on every line: a chamber model slower than the regulator's, so the lead is taken.
  for (uint8_t i = 0; i < g_pi16_config.line_count; ++i) {
    g_pi16_config.lines[i].chamber_tau_us = 40000;
    g_pi16_config.lines[i].overdrive_pa = 20000;
    g_pi16_config.lines[i].slew_pa_per_s = 0;
  }
#endif
#ifdef PALPA_BENCH_CORRECTED
  // A regulator correction on every line, as calibration measures one (8 points, commands from 10
  // to 90 % of the range; the regulator short of its command a little more towards the top, and
  // further short rising than falling): a calibrated line's feed-forward looks it up every tick.
  constexpr int kPoints = 8;
  for (uint8_t i = 0; i < g_pi16_config.line_count; ++i) {
    protocol::ConfigureLine& line = g_pi16_config.lines[i];
    const float low = static_cast<float>(line.command_min_pa);
    const float span = static_cast<float>(line.command_max_pa - line.command_min_pa);
    const float toward = span > 0 ? 1.0f : -1.0f;
    line.correction_count = kPoints;
    for (int k = 0; k < kPoints; ++k) {
      const float u = static_cast<float>(k) / static_cast<float>(kPoints - 1);
      const float command = low + span * (0.1f + 0.8f * u);
      line.correction[k] = {static_cast<int32_t>(command),
                            static_cast<int32_t>(command * (0.96f - 0.03f * u) - 400 * toward),
                            static_cast<int32_t>(command * (0.99f - 0.02f * u) + 300 * toward)};
    }
  }
#endif
  return &g_pi16_config;
}
#endif

}  // namespace
}  // namespace palpa::boards::mps2
