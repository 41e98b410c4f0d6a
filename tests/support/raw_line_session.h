// An in-process simulated board (thesis-5finger) in virtual time, its lines driven by raw
// setpoints as a host would send them: what the step benchmarks measure the line pipeline with.
#pragma once

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>

#include "palpa/core/board.h"
#include "palpa/hal/fake/fakes.h"
#include "palpa/protocol/codec.h"
#include "sim_board.h"

namespace palpa::bench {

class RawLineSession {
 public:
  /// `edit` changes each line's configuration before the steps (nothing when empty); fingers 0
  /// and 3 go to raw mode, so lines 0 (pressure), 3 (bias) and 5 (vacuum) take raw setpoints.
  explicit RawLineSession(const sim::PlantOptions& plant,
                          const std::function<void(protocol::ConfigureLine&)>& edit = {}) {
    sim::SimBoardOptions o;
    o.plant = plant;
    sim_ = sim::SimBoard::Create(o, link_).value;  // the default configuration: never refused
    Send(protocol::Hello{1, 0}, false);
    sim_->Advance(5);
    config_ = &sim_->board().config();
    if (edit) {
      for (uint8_t line : {0, 3, 5}) {
        protocol::ConfigureLine c = config_->lines[line];
        edit(c);
        Send(c, true);
      }
    }
    Send(protocol::SetFingerMode{0, protocol::FingerMode::kRaw}, true);
    Send(protocol::SetFingerMode{3, protocol::FingerMode::kRaw}, true);
    sim_->Advance(5);
  }

  /// New raw setpoints for the lines named.
  void Set(std::initializer_list<protocol::LineSetpoint> entries) {
    protocol::SetLineSetpoints sp{};
    sp.session = 1;  // the Hello's nonce
    sp.generation = ++generation_;
    for (const protocol::LineSetpoint& e : entries) sp.entries[sp.entry_count++] = e;
    Send(sp, false);
  }

  /// One millisecond of board and plant, the host's heartbeat every 20 ms.
  void Tick() {
    if (++ms_ % 20 == 0) Send(protocol::Heartbeat{1, ++generation_}, false);
    sim_->Advance(1000);
    link_.tx.clear();
  }

  double Chamber(uint8_t line) const { return sim_->plant().regulator(line).chamber_pa(); }
  /// What the board's sensor reads, through the line's configured transfer function.
  double Measured(uint8_t line) const {
    const protocol::ConfigureLine& c = config_->lines[line];
    const double counts = sim_->plant().SensorCounts(line);
    return c.sensor_min_pa + (counts - c.sensor_counts_min) * (c.sensor_max_pa - c.sensor_min_pa) /
                                 static_cast<double>(c.sensor_counts_max - c.sensor_counts_min);
  }
  /// The board's state of the line (its shaping models) and what it commanded the regulator.
  const core::LineState& LineStateOf(uint8_t line) const { return sim_->board().line_state(line); }
  double Command(uint8_t line) const { return sim_->board().line_output(line).command_pa; }
  uint8_t Status(uint8_t line) const { return sim_->board().line_output(line).status; }
  uint32_t Faults() const { return sim_->board().latched_faults(); }
  /// The lines whose own dump valves the board opens (bit i: line i), and the plant's valves.
  uint32_t Vents() const { return sim_->board().line_vents(); }
  uint32_t PlantVents() const { return sim_->plant().line_vents(); }
  bool Safe() const { return sim_->board().safe(); }
  sim::Plant& plant() { return sim_->plant(); }
  /// The line's configuration as the board runs it (after `edit`).
  const protocol::ConfigureLine& Config(uint8_t line) const { return config_->lines[line]; }
  /// The line's shaped steps fell back to unshaped ones (its outlet ran ahead of the model).
  bool ShapingFellBack(uint8_t line) const {
    return sim_->board().line_state(line).shaping_fell_back;
  }

 private:
  template <class M>
  void Send(const M& m, bool reliable) {
    uint8_t frame[protocol::kMaxFrameSize];
    const auto n = protocol::EncodeMessageFrame(
        m, reliable ? seq_++ : 0, reliable ? protocol::flags::kReliable : 0, frame, sizeof(frame));
    link_.Inject(frame, n.value);
    sim_->Advance(sim_->now_us() % 1000 == 0 ? 1 : 0);  // dispatched between ticks
  }

  hal::fake::FakeByteLink link_;
  std::unique_ptr<sim::SimBoard> sim_;
  const core::BoardConfig* config_ = nullptr;
  uint8_t seq_ = 0;
  uint32_t generation_ = 0;
  uint32_t ms_ = 0;
};

}  // namespace palpa::bench
