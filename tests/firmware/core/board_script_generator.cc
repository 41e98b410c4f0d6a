// Board scripts from a fixed seed (see board_script_generator.h). The bytes follow the argument
// order of board_script.cc's operations, so each operation reads what was written for it.
#include "board_script_generator.h"

#include "board_script.h"
#include "palpa/core/board_configs.h"

namespace palpa::testing {

uint64_t BoardScriptGenerator::Random() {
  uint64_t z = state_ += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

void BoardScriptGenerator::PutRandom(uint32_t count) {
  for (uint32_t i = 0; i < count; ++i) Put(Byte());
}

void BoardScriptGenerator::Spread(uint8_t decade, bool negative) {
  Put(static_cast<uint8_t>(decade % 10 | (negative ? 0x80 : 0)));
  Put(Byte());
}

std::vector<uint8_t> BoardScriptGenerator::Next() {
  out_.clear();
  Put(static_cast<uint8_t>(Below(core::kBoardConfigCount)));
  Put(0);  // a session
  Put(Byte());
  const uint32_t operations = 30 + Below(30);
  for (uint32_t i = 0; i < operations; ++i) {
    const uint32_t pick = Below(100);
    if (pick < 28) {
      Ticks();
    } else if (pick < 42) {
      Target();
    } else if (pick < 54) {
      SessionMessage();
    } else if (pick < 62) {
      Compensator();
    } else if (pick < 66) {
      Hardware();
    } else if (pick < 74) {
      Put(9);  // clear faults; one in four goes back to the factory configuration
      Put(Byte());
    } else if (pick < 79) {
      Update();
    } else if (pick < 83) {
      EndSession();
    } else if (pick < 87) {
      EditedRecord();
    } else if (pick < 93) {
      Put(0);  // a new session
      Put(Byte());
    } else if (pick < 97) {
      Packet();
    } else {
      Garbage();
    }
  }
  return out_;
}

void BoardScriptGenerator::Ticks() {
  // Mostly heartbeats on (bit 7) and a plant that follows the model or the commands; sometimes
  // no plant and no heartbeat, so host silence ends the session.
  static constexpr uint8_t kPlants[] = {0x81, 0x81, 0x82, 0x81, 0x80, 0x82,
                                        0x81, 0x82, 0x81, 0x82, 0x01, 0x00};
  if (Below(2) == 0) Target();  // the board holds its outputs safe until it is given a target
  Put(1);
  Put(kPlants[Below(sizeof(kPlants))]);
  Put(static_cast<uint8_t>(Below(100)));
}

void BoardScriptGenerator::Target() {
  Put(5);
  Put(Byte());                                       // finger
  Put(static_cast<uint8_t>(Below(6) == 0 ? 1 : 0));  // raw mode one time in six
  // Targets across the fingers' ranges (µm or mN/mm), sometimes any 16-bit value.
  PutWord(static_cast<uint16_t>(Below(8) == 0 ? Byte() << 8 | Byte() : Below(1600)));
}

void BoardScriptGenerator::Compensator() {
  Put(7);
  Put(Byte());  // finger
  const uint32_t kind = Below(20);
  if (kind < 12) {  // PI, or asymmetric PI
    const bool api = kind >= 8;
    const uint8_t operators = static_cast<uint8_t>(1 + Below(api ? 12 : 24));
    Put(api ? 2 : 1);
    Put(static_cast<uint8_t>(operators - 1));
    Spread(4, Below(2) == 0);                           // offset ≈ ±1e-2
    Spread(static_cast<uint8_t>(4 + Below(2)), false);  // w0 ≈ 1e-2 … 1e-1
    for (uint8_t i = 0; i < operators; ++i) Put(static_cast<uint8_t>(3 + Below(15)));  // r
    for (uint8_t i = 0; i < operators; ++i) Spread(3, Below(8) == 0);                  // w ≈ 1e-3
    if (api) {
      const uint8_t zones = static_cast<uint8_t>(Below(8));  // 1 + zones % 8 dead zones
      Put(zones);
      for (uint8_t i = 0; i <= zones; ++i) Put(static_cast<uint8_t>(1 + Below(40)));
      for (uint8_t i = 0; i <= zones; ++i) Spread(3, Below(4) == 0);
    }
  } else if (kind < 17) {  // branch: band, dead band, y, rising, falling
    const uint8_t points = static_cast<uint8_t>(2 + Below(12));
    Put(0);
    Put(static_cast<uint8_t>(points - 1));
    Spread(5, false);
    Put(static_cast<uint8_t>(Below(10)));
    for (uint8_t i = 0; i < points; ++i) Put(static_cast<uint8_t>(5 + Below(40)));
    for (uint8_t i = 0; i < 2 * points; ++i) Put(static_cast<uint8_t>(2 + Below(20)));
  } else {  // any kind, any bit patterns
    const uint8_t size = static_cast<uint8_t>(1 + Below(31));
    Put(3);
    Put(static_cast<uint8_t>(size - 1));
    Put(Byte());
    PutRandom(4u * size);
  }
}

void BoardScriptGenerator::Hardware() {
  Put(6);
  const uint8_t what = Byte();
  Put(what);
  switch (what % 4) {
    case 0:  // a sensor reading anywhere in the converter's range
      PutWord(static_cast<uint16_t>(Below(16384)));
      break;
    case 1:  // the E-stop pin
    case 2:  // a failing DAC
      PutWord(static_cast<uint16_t>(Below(3) == 0 ? 1 : 0));
      break;
    default:  // a silence of up to 0.3 s, sometimes up to 6.5 s
      PutWord(static_cast<uint16_t>(Below(4) == 0 ? Byte() << 8 | Byte() : Below(3000)));
      break;
  }
}

void BoardScriptGenerator::Update() {
  // The update operation's first byte: kind % 6, the slot in bit 4, a flag in bit 7.
  auto op = [this](uint8_t kind, uint8_t slot, bool flag) {
    Put(8);
    uint8_t what = kind;
    while ((what >> 4 & 1) != slot || (what >> 7) != (flag ? 1 : 0) || what % 6 != kind) ++what;
    Put(what);
  };
  const uint8_t slot = Below(6) == 0 ? 0 : 1;  // mostly the inactive slot
  switch (Below(6)) {
    case 0:  // enter, erase, a few writes, activate
      op(0, slot, false);
      PutWord(static_cast<uint16_t>(64 + Below(256)));
      op(1, slot, false);
      PutWord(0);
      PutWord(static_cast<uint16_t>(32 + Below(64)));
      for (uint32_t k = 0, n = 1 + Below(4); k < n; ++k) {
        op(2, slot, false);
        const uint8_t size = static_cast<uint8_t>(Below(200));
        Put(size);
        PutRandom(size + 1u);
      }
      op(3, slot, false);
      break;
    case 1: {  // a whole image (sometimes damaged or for another slot), then activate
      op(5, slot, false);
      const uint8_t flags = static_cast<uint8_t>(Below(4) == 0 ? Byte() & 0x0F : 0);
      const uint8_t body = static_cast<uint8_t>(16 + Below(200));
      Put(flags);
      Put(body);
      if ((flags & 2) != 0) PutWord(Byte());
      if ((flags & 4) != 0) Put(Byte());
      Put(2);  // version 2.0
      Put(0);
      Put(static_cast<uint8_t>(Below(5)));  // rollback counter, the floor is 2
      PutRandom(body);
      if ((flags & 8) != 0) PutRandom(3);
      op(3, slot, false);
      break;
    }
    case 2:  // confirm
      op(4, slot, false);
      break;
    default: {  // one message with fields anywhere
      const uint8_t kind = static_cast<uint8_t>(Below(5));
      op(kind, slot, Below(2) == 0);
      PutRandom(kind == 2 ? 4 + Below(40) : 4);
      break;
    }
  }
}

void BoardScriptGenerator::EndSession() {
  // 0 Close, 1 Release, 2 a second host's Hello, 3 Close twice; bit 4 names another session.
  const uint8_t what = static_cast<uint8_t>(Below(4) | (Below(4) == 0 ? 0x10 : 0));
  Put(10);
  Put(what);
  if ((what & 0x10) != 0) Put(Byte());
  if (what % 4 == 2) PutRandom(2);
}

void BoardScriptGenerator::SessionMessage() {
  // Raw setpoints most often; then EStop, GetConfig, SaveConfig, loop statistics, diagnostics,
  // the slots, ClearFault.
  const uint8_t what = static_cast<uint8_t>(Below(3) == 0 ? Below(8) : 0);
  const uint8_t line = static_cast<uint8_t>(Below(8));
  if (what == 0 && Below(2) == 0) {  // first the finger of that number to raw mode (often its)
    Put(5);
    Put(line);
    Put(1);
    PutWord(0);
  }
  Put(11);
  Put(what);
  if (what == 0) {
    Put(line);
    Put(static_cast<uint8_t>(Below(2) == 0 ? Below(200) : Byte()));  // up to 127 % of the span
  } else if (what == 2) {
    Put(Byte());
    Put(static_cast<uint8_t>(Below(10)));
    Put(static_cast<uint8_t>(Below(3) == 0 ? Byte() : 0));
  } else if (what == 7) {
    PutWord(static_cast<uint16_t>(Byte() << 8 | Byte()));
  }
}

void BoardScriptGenerator::Packet() {
  Put(2);
  Put(Below(2) == 0 ? Byte() : static_cast<uint8_t>(Below(48)));  // type
  const uint8_t mode = Byte();
  const uint8_t size = static_cast<uint8_t>(Below(48));
  Put(mode);
  Put(size);
  PutRandom(size);
  if (mode % 2 != 0) Put(Byte());  // seq
}

void BoardScriptGenerator::Garbage() {
  const uint8_t size = static_cast<uint8_t>(Below(64));
  Put(3);
  Put(size);
  for (uint8_t i = 0; i < size; ++i) Put(Below(8) == 0 ? 0 : Byte());  // delimiters among them
}

void BoardScriptGenerator::EditedRecord() {
  const uint8_t edits = static_cast<uint8_t>(Below(4));
  Put(4);
  Put(Byte());  // record
  Put(edits);
  for (uint8_t e = 0; e < edits; ++e) PutRandom(3);  // where, what
  Put(Byte());                                       // sent directly or staged
}

}  // namespace palpa::testing
