// The board fuzzer's firmware-update operations and their checks (see board_fuzz_update.h).
#include "board_fuzz_update.h"
#include "development_signer.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "palpa/protocol/codec.h"
#include "palpa/protocol/image.h"
#include "palpa/protocol/sha256.h"

namespace palpa::testing {
namespace {

namespace pp = protocol;
constexpr const core::FlashLayout& kLayout = core::kDefaultLayout;
constexpr uint32_t kProtectedEnd = kLayout.slot_offset[0] + kLayout.slot_size;
constexpr uint8_t kRunningSlot = 0;
constexpr uint32_t kRollbackFloor = 2;  ///< images with a lower counter must be refused

/// The boot state of a board running a confirmed image from slot 0 that raised the floor.
bool WriteBootState(hal::Flash& flash) {
  core::BootState state;
  state.confirmed = kRunningSlot;
  state.rollback_floor = kRollbackFloor;
  return core::BootStore(&flash, kLayout).Save(state) == pp::Status::kOk;
}

template <typename Message>
void Encode(const Message& m, pp::MessageType type, const SendMessage& send) {
  uint8_t body[pp::kMaxBodySize];
  const pp::Result<size_t> n = pp::EncodeBody(m, body, sizeof(body));
  if (n.ok()) send(static_cast<uint8_t>(type), body, n.value);
}

}  // namespace

void BoardFuzzFail(const char* what, unsigned line) {
  std::fprintf(stderr, "board fuzz: %s (line, channel or slot %u)\n", what, line);
  std::abort();
}

UpdateFuzzer::UpdateFuzzer()
    : flash_(kLayout.total, kLayout.sector_size),
      boot_state_written_(WriteBootState(flash_)),
      engine_(&flash_, kLayout, pp::BoardKind::kSim, kRunningSlot) {
  if (!boot_state_written_) BoardFuzzFail("the boot state could not be written", 0);
  // A few programmed bytes in every sector (a whole image costs more than the rest of an
  // input): an erase or a write anywhere in the protected range changes some byte of it.
  for (uint32_t sector = 0; sector < kProtectedEnd; sector += kLayout.sector_size) {
    for (uint32_t k = 0; k < 16; ++k) {
      const uint8_t mark = static_cast<uint8_t>(k * 37u + sector / kLayout.sector_size);
      flash_.Program(sector + k * 509u % kLayout.sector_size, &mark, 1);
    }
  }
  protected_bytes_.assign(flash_.contents().begin(), flash_.contents().begin() + kProtectedEnd);
}

bool UpdateFuzzer::ProtectedIntact() const {
  return std::memcmp(flash_.contents().data(), protected_bytes_.data(), kProtectedEnd) == 0;
}

void UpdateFuzzer::Send(FuzzInput& s, const SendMessage& send) {
  const uint32_t sequence = BootStateNow().sequence;
  const uint8_t what = s.Byte();
  const uint8_t slot = (what >> 4) % 2;
  switch (what % 6) {
    case 0:
      Encode(pp::UpdateEnter{slot, s.Word() * 64u}, pp::MessageType::kUpdateEnter, send);
      break;
    case 1:
      Encode(pp::UpdateErase{slot, s.Word() * 256u, s.Word() * 256u}, pp::MessageType::kUpdateErase,
             send);
      break;
    case 2: {
      pp::UpdateWrite m{};
      m.slot = slot;
      m.offset = (what & 0x80) != 0 ? s.Word() * 4u : next_write_;
      m.data_size = static_cast<uint8_t>(1 + s.Byte() % pp::kMaxUpdateChunk);
      for (uint8_t i = 0; i < m.data_size; ++i) m.data[i] = s.Byte();
      next_write_ = m.offset + m.data_size;
      Encode(m, pp::MessageType::kUpdateWrite, send);
      break;
    }
    case 3: {
      pp::UpdateActivate m{};
      m.slot = slot;
      m.image_size = (what & 0x80) != 0 ? s.Word() * 4u : next_write_;
      const uint32_t at = kLayout.slot_offset[slot];
      if (m.image_size <= 16 * 1024)  // hashing a whole slot would cost more than the input
        m.image_sha256 = pp::Sha256Of(flash_.contents().data() + at, m.image_size);
      Encode(m, pp::MessageType::kUpdateActivate, send);
      break;
    }
    case 4:
      Encode(pp::UpdateConfirm{slot}, pp::MessageType::kUpdateConfirm, send);
      break;
    default:
      SendWholeImage(s, slot, send);
      break;
  }
  if (!ProtectedIntact())
    BoardFuzzFail("an update message changed the bootloader or the running slot", slot);
  CheckTrial(sequence);
}

/// Enter and erase (unless the flags skip them), then an image built with fuzzed fields — board
/// kind, slot, load address, version, rollback counter, body, one damaged byte — written in
/// chunks from offset 0. A following activate takes it past the hash to the image checks.
void UpdateFuzzer::SendWholeImage(FuzzInput& s, uint8_t slot, const SendMessage& send) {
  const uint8_t flags = s.Byte();
  const uint8_t body_size = s.Byte();
  pp::ImageFields fields;
  fields.slot = (flags & 1) != 0 ? slot ^ 1 : slot;
  fields.load_address = kLayout.xip_base + kLayout.slot_offset[fields.slot];
  if ((flags & 2) != 0) fields.load_address += s.Word() * 4u;
  fields.board_kind = pp::BoardKind::kSim;
  if ((flags & 4) != 0) fields.board_kind = static_cast<pp::BoardKind>(s.Byte());
  fields.version_major = s.Byte();
  fields.version_minor = s.Byte();
  fields.rollback_counter = s.Byte();
  std::vector<uint8_t> image_body(body_size);
  for (uint8_t& b : image_body) b = s.Byte();
  std::vector<uint8_t> image(pp::ImageSize(body_size));
  const uint32_t size =
      pp::WriteImage(fields, image_body.data(), body_size, image.data(),
                     static_cast<uint32_t>(image.size()), &palpa::testing::DevelopmentSigner());
  if ((flags & 8) != 0) image[s.Word() % image.size()] ^= static_cast<uint8_t>(1 + s.Byte() % 255);
  if ((flags & 16) == 0) {
    Encode(pp::UpdateEnter{slot, size}, pp::MessageType::kUpdateEnter, send);
    const uint32_t sector = kLayout.sector_size;
    Encode(pp::UpdateErase{slot, 0, (size + sector - 1) / sector * sector},
           pp::MessageType::kUpdateErase, send);
  }
  for (uint32_t at = 0; at < size; at += pp::kMaxUpdateChunk) {
    pp::UpdateWrite m{};
    m.slot = slot;
    m.offset = at;
    m.data_size = static_cast<uint8_t>(std::min<uint32_t>(pp::kMaxUpdateChunk, size - at));
    std::memcpy(m.data.data(), image.data() + at, m.data_size);
    Encode(m, pp::MessageType::kUpdateWrite, send);
  }
  next_write_ = size;
}

core::BootState UpdateFuzzer::BootStateNow() { return core::BootStore(&flash_, kLayout).Load(); }

/// Only right after the message that marked the slot: the board resets once that Ack is out,
/// so what later messages do to the slot is the bootloader's to judge (it checks again).
void UpdateFuzzer::CheckTrial(uint32_t sequence_before) {
  const core::BootState state = BootStateNow();
  if (state.sequence == sequence_before || state.trial_state != core::TrialState::kPending) return;
  if (state.trial >= 2)
    BoardFuzzFail("the boot state names a trial slot that does not exist", state.trial);
  const core::SlotImage slot = core::InspectSlot(flash_, kLayout, state.trial, pp::BoardKind::kSim);
  if (!slot.valid)
    BoardFuzzFail("an activated slot does not hold a valid image for this board", state.trial);
  if (slot.info.rollback_counter < state.rollback_floor)
    BoardFuzzFail("an activated image is older than the rollback floor", state.trial);
}

}  // namespace palpa::testing
