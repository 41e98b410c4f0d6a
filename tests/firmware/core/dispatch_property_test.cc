// Property: whatever arrives on the link — valid, invalid, out of limit, duplicated, reordered —
// every out-of-limit setpoint is Nacked and no DAC code ever leaves a line's limits or ceiling.
#include <random>
#include <string>
#include <vector>

#include "board_harness.h"
#include "dac_pressure.h"
#include "palpa/core/ceilings.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::BoardFrame;
using palpa::testing::BoardHarness;
namespace pp = palpa::protocol;
namespace pc = palpa::core;

namespace {

using palpa::testing::PressureOfCounts;

struct Generator {
  std::mt19937 rng;
  const pc::BoardConfig& config;
  uint32_t generation = 1;

  int32_t Pressure(uint8_t line, bool out_of_limit) {
    const pp::ConfigureLine& c = config.lines[line];
    if (!out_of_limit)
      return c.limit_min_pa +
             static_cast<int32_t>(rng() %
                                  static_cast<uint32_t>(c.limit_max_pa - c.limit_min_pa + 1));
    // Beyond whichever limit the wire range leaves room to exceed.
    const int32_t excess = 1 + static_cast<int32_t>(rng() % 20000);
    const bool above = c.limit_max_pa == pp::kMaxPressurePa   ? false
                       : c.limit_min_pa == pp::kMinPressurePa ? true
                                                              : rng() % 2 == 0;
    const int32_t v = above ? c.limit_max_pa + excess : c.limit_min_pa - excess;
    return v > pp::kMaxPressurePa ? pp::kMaxPressurePa
                                  : (v < pp::kMinPressurePa ? pp::kMinPressurePa : v);
  }
};

}  // namespace

TEST_GROUP(DispatchProperty){};

TEST(DispatchProperty, OutOfLimitSetpointsAreNackedAndTheDacStaysWithinLimits) {
  BoardHarness h;
  const pc::BoardConfig& config = h.board->config();
  Generator g{std::mt19937(99), config};
  std::vector<std::vector<uint8_t>> sent;  // for duplicates and reordering
  uint32_t out_of_limit_sent = 0, out_of_limit_nacked = 0, frames = 0;
  h.Connect();
  for (uint8_t f = 0; f < config.finger_count; ++f)
    h.Send(pp::SetFingerMode{f, f % 2 ? pp::FingerMode::kRaw : pp::FingerMode::kTarget});
  h.Drain();

  for (int sequence = 0; sequence < 100000; ++sequence) {
    const int kind = static_cast<int>(g.rng() % 100);
    bool expect_nack = false;
    uint8_t frame[pp::kMaxFrameSize];
    size_t n = 0;
    if (kind < 45) {  // setpoints, a third of them out of limit
      pp::SetLineSetpoints m{};
      m.session = h.hello_nonce;
      m.generation = ++g.generation;
      m.entry_count = static_cast<uint8_t>(1 + g.rng() % 3);
      for (uint8_t i = 0; i < m.entry_count; ++i) {
        const uint8_t line = static_cast<uint8_t>(g.rng() % config.line_count);
        const bool bad = g.rng() % 3 == 0;
        m.entries[i] = {line, g.Pressure(line, bad)};
        expect_nack |= bad;
      }
      n = pp::EncodeMessageFrame(m, 0, 0, frame, sizeof(frame)).value;
      out_of_limit_sent += expect_nack;
    } else if (kind < 65) {  // finger targets, some beyond the curve or with the wrong unit
      pp::SetFingerTargets m{};
      m.session = h.hello_nonce;
      m.generation = ++g.generation;
      m.entry_count = 1;
      const uint8_t f = static_cast<uint8_t>(g.rng() % config.finger_count);
      m.entries[0] = {f, pc::UnitOf(config.fingers[f].kind), static_cast<int32_t>(g.rng() % 6000)};
      if (g.rng() % 10 == 0) m.entries[0].unit = static_cast<pp::OutputUnit>(g.rng() % 2);
      n = pp::EncodeMessageFrame(m, 0, 0, frame, sizeof(frame)).value;
    } else if (kind < 75 && !sent.empty()) {  // an old frame again: duplicated or reordered
      const auto& old = sent[g.rng() % sent.size()];
      n = old.size();
      std::copy(old.begin(), old.end(), frame);
    } else if (kind < 85) {  // garbage, or a valid frame with a flipped bit
      n = 1 + g.rng() % 60;
      for (size_t i = 0; i < n; ++i) frame[i] = static_cast<uint8_t>(g.rng());
      frame[n++] = 0;
    } else if (kind < 90) {
      n = pp::EncodeMessageFrame(pp::ClearFault{}, static_cast<uint8_t>(g.rng()),
                                 pp::flags::kReliable, frame, sizeof(frame))
              .value;
    } else if (kind < 93) {
      n = pp::EncodeMessageFrame(pp::EStop{}, 0, 0, frame, sizeof(frame)).value;
    } else {
      n = pp::EncodeMessageFrame(pp::Heartbeat{h.hello_nonce, ++g.generation}, 0, 0, frame,
                                 sizeof(frame))
              .value;
    }
    h.link.Inject(frame, n);
    h.board->Step();
    if (sequence % 4 == 0) sent.emplace_back(frame, frame + n);
    if (sent.size() > 64) sent.erase(sent.begin());
    ++frames;
    const auto answers = h.Drain();
    if (expect_nack) {
      const pp::Status s = BoardHarness::AnswerFor(answers, pp::MessageType::kSetLineSetpoints);
      CHECK_TEXT(s != pp::Status::kOk && s != pp::Status::kUnavailable,
                 std::to_string(sequence).c_str());
      out_of_limit_nacked += s != pp::Status::kUnavailable;
    }
    h.Run(1);
    h.FollowCommands();
    for (uint8_t i = 0; i < config.line_count; ++i) {
      const pp::ConfigureLine& c = config.lines[i];
      const float pa = PressureOfCounts(c, h.dac.counts[i]);
      const pc::Ceiling ceiling = pc::CeilingFor(c.kind);
      const float lsb = 100000.0f / 4095.0f;
      CHECK(pa >= static_cast<float>(c.limit_min_pa) - lsb &&
            pa <= static_cast<float>(c.limit_max_pa) + lsb);
      CHECK(pa >= static_cast<float>(ceiling.min_pa) - lsb &&
            pa <= static_cast<float>(ceiling.max_pa) + lsb);
    }
    if (sequence % 500 == 0) {  // keep the session alive and faults clearable
      h.Connect(static_cast<uint8_t>(g.rng()));
      h.Send(pp::ClearFault{});
      h.Drain();
    }
  }
  LONGS_EQUAL(out_of_limit_sent, out_of_limit_nacked);
  CHECK(out_of_limit_sent > 10000);
  CHECK(frames == 100000);
}
