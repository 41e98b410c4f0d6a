// Board scripts (board_script.h) from a fixed seed: sessions that configure compensators, drive
// targets and raw setpoints, edit and stage configurations, update, read back, and meet garbage,
// hardware events and silences — the board fuzzer's kinds, shaped so most operations are ones a
// board acts on rather than refuses.
#pragma once

#include <cstdint>
#include <vector>

namespace palpa::testing {

class BoardScriptGenerator {
 public:
  explicit BoardScriptGenerator(uint64_t seed) : state_(seed) {}

  /// The next script; the same seed gives the same scripts on every machine and compiler.
  std::vector<uint8_t> Next();

 private:
  uint64_t Random();  ///< splitmix64
  uint32_t Below(uint32_t n) { return static_cast<uint32_t>(Random() % n); }
  uint8_t Byte() { return static_cast<uint8_t>(Random()); }
  void Put(uint8_t b) { out_.push_back(b); }
  void PutWord(uint16_t w) {
    Put(static_cast<uint8_t>(w));
    Put(static_cast<uint8_t>(w >> 8));
  }
  void PutRandom(uint32_t count);
  /// A value for the script's `spread`: decade code (b % 10 → 10^(b % 10 - 6)) and mantissa.
  void Spread(uint8_t decade, bool negative);

  void Ticks();
  void Target();
  void Compensator();
  void Hardware();
  void Update();
  void EndSession();
  void SessionMessage();
  void Packet();
  void Garbage();
  void EditedRecord();

  uint64_t state_;
  std::vector<uint8_t> out_;
};

}  // namespace palpa::testing
