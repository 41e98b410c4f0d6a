// A simulated board driven in-process through the protocol on free-running virtual time: frames
// in, heartbeats every 20 ms, replies discarded. Shared by the finger rig and the calibration rig.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "palpa/hal/fake/fakes.h"
#include "palpa/protocol/codec.h"
#include "sim_board.h"

namespace palpa::testing {

/// A level-3 plant behind `config`, with the given actuator unit, seed and second-order effects.
sim::SimBoardOptions PlantBoardOptions(const std::string& config, uint32_t unit, uint32_t seed,
                                       sim::Effects effects);

class InProcessBoard {
 public:
  explicit InProcessBoard(const sim::SimBoardOptions& options);

  /// Sends a message (reliable messages get the next sequence number) and serves it.
  template <class M>
  void Send(const M& m, bool reliable = M::kInfo.delivery == protocol::Delivery::kReliable) {
    uint8_t frame[protocol::kMaxFrameSize];
    const auto n = protocol::EncodeMessageFrame(
        m, reliable ? seq_++ : 0, reliable ? protocol::flags::kReliable : 0, frame, sizeof(frame));
    link_.Inject(frame, n.value);
    sim_->Advance(1);  // dispatched between ticks
  }
  /// Sends a configuration record that may exceed a packet (staged when it does).
  template <class M>
  void SendConfig(const M& m);
  /// Runs `ms` milliseconds of plant and board, heartbeating.
  void Run(int ms);
  /// The line's pressure as its sensor reads it (Pa), through the configured transfer function.
  double SensorPa(uint8_t line) const;
  uint32_t next_generation() { return ++generation_; }
  /// The session every stream frame names: the nonce of this board's Hello.
  static constexpr uint32_t kSession = 1;

  sim::SimBoard& sim() { return *sim_; }
  const sim::SimBoard& sim() const { return *sim_; }
  const core::BoardConfig& config() const { return sim_->board().config(); }

 private:
  hal::fake::FakeByteLink link_;
  std::unique_ptr<sim::SimBoard> sim_;
  uint8_t seq_ = 0;
  uint32_t generation_ = 0;
  int since_heartbeat_ms_ = 0;
};

}  // namespace palpa::testing
