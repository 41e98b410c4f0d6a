// A Board on fakes, with helpers to talk to it as a host would and to run virtual time.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "palpa/core/board.h"
#include "palpa/core/board_configs.h"
#include "palpa/core/update_engine.h"
#include "palpa/hal/fake/fakes.h"
#include "palpa/hal/fake/simulated_nor_flash.h"
#include "palpa/protocol/codec.h"
#include "received_frame.h"

namespace palpa::testing {

namespace pp = palpa::protocol;
namespace pc = palpa::core;
namespace fake = palpa::hal::fake;

using BoardFrame = ReceivedFrame;

struct BoardHarness {
  /// `update`: the engine that takes firmware updates over the link (none: they are refused).
  explicit BoardHarness(const char* config_name = "thesis-5finger",
                        pp::ResetCause reset_cause = pp::ResetCause::kPowerOn,
                        fake::SimulatedNorFlash* shared_flash = nullptr,
                        pc::UpdateEngine* update = nullptr);

  fake::FakeClock clock;
  fake::FakeAnalogOutput dac;
  fake::FakeAnalogInput adc;
  fake::FakeDigitalOutput supply, dump, pump;
  fake::FakeDigitalPort vents;  ///< the lines' own dump valve drivers (BoardIo::line_vents)
  fake::FakeDigitalInput estop;
  fake::FakeByteLink link;
  fake::SimulatedNorFlash own_flash{64 * 1024, 8 * 1024};
  fake::SimulatedNorFlash* flash;
  std::unique_ptr<pc::Board> board;
  /// Called after every loop pass the harness runs: whether a tick ran, and the bytes the board
  /// sent during it.
  std::function<void(bool ticked, const uint8_t* sent, size_t size)> after_step;
  pp::OwningFrameDecoder decoder;
  uint8_t next_seq = 0;
  uint32_t generation = 0;

  /// Sends a message (reliable ones get the next seq) and runs one loop pass. A message naming a
  /// session with none named (0) names the harness's: the nonce of its last Hello.
  template <class M>
  void Send(M m, bool reliable = M::kInfo.delivery == pp::Delivery::kReliable) {
    if constexpr (requires { m.session; }) {
      if (m.session == 0) m.session = hello_nonce;
    }
    uint8_t frame[pp::kMaxFrameSize];
    const uint8_t seq = reliable ? next_seq++ : 0;
    const auto n =
        pp::EncodeMessageFrame(m, seq, reliable ? pp::flags::kReliable : 0, frame, sizeof(frame));
    link.Inject(frame, n.value);
    Step();
  }
  /// One loop pass (after_step sees it); true when a tick ran.
  bool Step();
  /// Opens a session (Hello; the open one, if any, closed first) and returns the HelloReply.
  pp::HelloReply Connect(uint8_t initial_seq = 0);
  /// Runs `ms` milliseconds of virtual time, one loop pass per 1 ms tick (plus heartbeats if
  /// asked).
  void Run(uint32_t ms, bool heartbeat = false);
  /// Frames the board has sent since the last call.
  std::vector<BoardFrame> Drain();
  /// Every configured line's output at 0 Pa, every compiled configuration's safe value.
  bool AllLinesSafe() const;
  /// The last Ack or Nack in `frames` for message type `type`, as a status (kOk for Ack).
  static pp::Status AnswerFor(const std::vector<BoardFrame>& frames, pp::MessageType type);
  /// Sensor counts on every configured line that read `pa` (the ideal plant of these tests).
  void SetMeasured(uint8_t line, float pa);
  /// Makes every sensor read what its line commands (a regulator and chamber with no lag).
  void FollowCommands();
  /// Makes every sensor read the line's regulator-model reference (a plant exactly as modelled).
  void FollowModel();
  uint32_t hello_nonce = 0x1234;
  float CommandedPa(uint8_t line) const;
};

}  // namespace palpa::testing
