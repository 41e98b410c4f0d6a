// A script of operations run against the whole board behind its link, with the board fuzzer's
// checks after every loop pass: what the board fuzzer runs, and what the behaviour digest runs.
//
// Whatever arrives — packets of any type and body, garbage bytes, configurations edited
// anywhere and sent directly or staged, sensor counts of any value, the E-stop pin, a failing
// DAC, long silences — the board must not crash or invoke undefined behaviour, and:
//  * every configured line's DAC code commands a pressure within the line's limits and its
//    kind's hard ceiling (checked after every tick against the configuration the tick ran with);
//  * a channel a configuration dropped holds the safe code of the line it last had;
//  * a refused configuration message changes nothing of the live configuration;
//  * every commanded pressure is finite;
//  * while an update is under way every line holds its safe code, no update message ever
//    changes the bootloader or the running image's slot, and an activated slot holds a valid
//    image the rollback floor allows (board_fuzz_update.cc);
//  * a Close of the session ends it and a Release keeps it, both with every line at its safe
//    code from the next tick and no fault latched for them; a Close during an update leaves what
//    was written resumable; a Close or Release of another session, a repeated Close and a second
//    host's Hello change nothing (no_session, busy).
// A broken guarantee aborts (BoardFuzzFail), so libFuzzer keeps the input.
//
// The script: byte 0 picks the compiled-in configuration, then operations follow, each an opcode
// byte (modulo kOperations) and its arguments (missing bytes read as 0):
//   0 a new session [seq]          1 time passes [plant, ms-1]     2 any packet [type, mode, ...]
//   3 raw bytes [size, bytes]      4 an edited configuration record  5 a finger's mode and target
//   6 a hardware event             7 a compensator for a finger     8 an update message
//   9 clear faults (factory reset)  10 Close, Release, a second Hello  11 a session message
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "board_fuzz_update.h"
#include "board_harness.h"
#include "fuzz_input.h"

namespace palpa::testing {

class BoardScript {
 public:
  static constexpr uint8_t kOperations = 12;

  /// After every loop pass, once the checks passed: whether a tick ran, and what the board sent.
  using StepObserver =
      std::function<void(const BoardHarness& h, bool ticked, const uint8_t* sent, size_t size)>;

  /// A board with the configuration the script's first byte names.
  BoardScript(const uint8_t* script, size_t size, StepObserver observer = nullptr);

  /// Runs every operation, then 20 more ticks under check.
  void Run();

 private:
  void Remember();
  void CheckOutputs(const core::BoardConfig& ran_with);
  void AfterStep(bool ticked, const uint8_t* sent, size_t size);
  void Step(uint8_t plant);
  void RunTicks(uint32_t ms, uint8_t plant, bool heartbeat);
  void SendPacket(uint8_t type, uint8_t seq, uint8_t flags, const uint8_t* body, size_t size);
  void SendReliable(uint8_t type, const uint8_t* body, size_t size);
  void SendEditedRecord();
  void SendCompensator();
  void SendSessionMessage();
  void CheckAllSafe(const char* what);
  template <class M>
  protocol::Status SendUnsequenced(const M& m);
  void EndSession();
  void Operate();

  FuzzInput s_;
  StepObserver observer_;
  UpdateFuzzer update_;  // before the board, which keeps a pointer to its engine
  BoardHarness h_;
  /// The configuration the next tick runs with (a loop pass ticks before it reads the link).
  core::BoardConfig ran_with_{};
  /// The last configuration each DAC channel had, for the dropped-channel check.
  std::array<protocol::ConfigureLine, hal::fake::kChannels> last_line_{};
  std::array<bool, hal::fake::kChannels> ever_configured_{};
};

}  // namespace palpa::testing
