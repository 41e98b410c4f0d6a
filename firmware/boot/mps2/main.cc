// The MPS2 AN386 bootloader: chooses a slot from the boot state and the images' checks (the
// choice firmware/core makes for every board), checks the chosen image's vector table, hands the
// core over (interrupts off and cleared, VTOR, stack pointer) and jumps. With no image that
// checks it stays in recovery mode: the bootstrap set over UART0, so `palpa flash` can write one.
#include <cstdint>
#include <type_traits>

#include "../../boards/common/reset_record.h"
#include "palpa/core/boot_state.h"
#include "palpa/core/update_engine.h"
#include "palpa/hal/mps2/code_flash.h"
#include "palpa/hal/mps2/drivers.h"
#include "palpa/hal/mps2/registers.h"
#include "palpa/protocol/codec.h"
#include "palpa/protocol/framing.h"

// The application's reset record, at the address both linker scripts give it.
extern palpa::boards::ResetRecord g_reset_record;

namespace {

namespace core = palpa::core;
namespace pp = palpa::protocol;
namespace mps2 = palpa::hal::mps2;

constexpr pp::BoardKind kKind = pp::BoardKind::kMps2An386;
constexpr uint32_t kRamStart = 0x20000000u, kRamEnd = 0x20400000u;

mps2::Uart g_uart;

/// The vector table an image starts with must point into RAM (stack) and into its own body
/// (reset handler, Thumb): anything else is not a program for this core.
bool VectorsPlausible(const core::FlashLayout& layout, uint8_t slot, const core::SlotImage& image) {
  const uint32_t base = layout.xip_base + layout.slot_offset[slot] + image.info.header_size;
  const auto* vectors = reinterpret_cast<const uint32_t*>(base);
  const uint32_t sp = vectors[0], pc = vectors[1];
  return sp > kRamStart && sp <= kRamEnd && sp % 8 == 0 && (pc & 1u) != 0 && pc > base &&
         pc < base + image.info.body_size;
}

[[noreturn]] void Jump(uint32_t vector_table) {
  asm volatile("cpsid i" ::: "memory");
  mps2::kSysTick->CSR = 0;
  for (int i = 0; i < 8; ++i) {
    mps2::kNvicIcer0[i] = 0xFFFFFFFFu;  // every interrupt disabled...
    mps2::kNvicIcpr0[i] = 0xFFFFFFFFu;  // ...and nothing left pending for the application
  }
  *mps2::kScbVtor = vector_table;
  const auto* vectors = reinterpret_cast<const uint32_t*>(vector_table);
  asm volatile(
      "msr msp, %0\n"
      "dsb\n"
      "isb\n"
      "cpsie i\n"
      "bx %1\n" ::"r"(vectors[0]),
      "r"(vectors[1])
      : "memory");
  for (;;) {
  }
}

template <class M>
void Send(const M& m, uint8_t seq, uint8_t flags) {
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(m, seq, static_cast<uint8_t>(flags | pp::flags::kFromBoard),
                                        frame, sizeof(frame));
  if (n.ok()) g_uart.Write(frame, n.value);
}

/// What recovery mode speaks: Hello, EStop and the update set. Other types are Nacked unsupported
/// without being decoded (their decoders would not fit the bootloader's 32 KiB beside the
/// signature check).
using RecoverySet =
    pp::MessageList<pp::Hello, pp::EStop, pp::UpdateEnter, pp::UpdateErase, pp::UpdateWrite,
                    pp::UpdateQuery, pp::UpdateActivate, pp::UpdateReboot, pp::SlotsQuery>;

/// Recovery mode: Hello, EStop and the update set; everything else is not spoken here.
[[noreturn]] void Recovery(core::UpdateEngine& engine, uint32_t floor) {
  constexpr uint32_t kBootNonce = 0x424F4F54u;  // "BOOT"
  // Why the board is here: a fault handler's or a reboot's record, or power-on.
  const pp::ResetCause cause = g_reset_record.Take();
  g_uart.Init();
  pp::OwningFrameDecoder decoder;
  bool reboot = false;
  for (;;) {
    uint8_t bytes[64];
    const size_t n = g_uart.Read(bytes, sizeof(bytes));
    for (size_t i = 0; i < n; ++i) {
      if (decoder.Process(bytes[i]) != pp::FrameDecoder::Event::kFrame) continue;
      const pp::Frame& frame = decoder.frame();
      const pp::Header& h = frame.header;
      const uint8_t reliable = h.flags & pp::flags::kReliable;
      auto answer = [&](pp::Status status, uint32_t detail) {
        if (status == pp::Status::kOk) {
          Send(pp::Ack{kBootNonce, h.type}, h.seq, reliable);
        } else {
          Send(pp::Nack{kBootNonce, h.type, status, detail}, h.seq, reliable);
        }
      };
      pp::FieldError field;
      const pp::Status decoded = pp::DispatchFrameOf<RecoverySet>(
          frame,
          [&](const auto& m, const pp::Header&) {
            using M = std::decay_t<decltype(m)>;
            uint32_t detail = 0;
            if constexpr (std::is_same_v<M, pp::Hello>) {
              pp::HelloReply r{};
              r.host_nonce = m.host_nonce;
              r.boot_nonce = kBootNonce;
              r.board_kind = kKind;
              r.protocol_version = pp::kProtocolVersion;
              r.catalog_hash = pp::kCatalogHash;
              r.reset_cause = cause;
              r.time_scale = 1.0f;
              r.rx_buffer_bytes = mps2::Uart::kRxSize;
              r.active_slot = static_cast<uint8_t>(1 - engine.inactive_slot());
              r.rollback_counter = floor;
              const char name[] = "recovery";
              for (size_t k = 0; k < sizeof(name); ++k) r.config_name[k] = name[k];
              Send(r, h.seq, 0);
            } else if constexpr (std::is_same_v<M, pp::EStop>) {
              answer(pp::Status::kOk, 0);  // every output is safe here already
            } else if constexpr (std::is_same_v<M, pp::UpdateEnter>) {
              answer(engine.Enter(m, &detail), detail);
            } else if constexpr (std::is_same_v<M, pp::UpdateErase>) {
              answer(engine.Erase(m, &detail), detail);
            } else if constexpr (std::is_same_v<M, pp::UpdateWrite>) {
              answer(engine.Write(m, &detail), detail);
            } else if constexpr (std::is_same_v<M, pp::UpdateQuery>) {
              pp::UpdateStatus s = engine.Query(m.slot);
              s.boot_nonce = kBootNonce;
              Send(s, h.seq, reliable);
            } else if constexpr (std::is_same_v<M, pp::UpdateActivate>) {
              answer(engine.Activate(m, &detail), detail);
            } else if constexpr (std::is_same_v<M, pp::UpdateReboot>) {
              answer(pp::Status::kOk, 0);
              reboot = true;
            } else if constexpr (std::is_same_v<M, pp::SlotsQuery>) {
              pp::SlotsReport s = engine.Slots();
              s.boot_nonce = kBootNonce;
              Send(s, h.seq, reliable);
            } else {
              answer(pp::Status::kUnsupported, 0);
            }
          },
          &field);
      if (decoded != pp::Status::kOk) answer(decoded, field.offset);
    }
    g_uart.PumpTx();
    if (reboot) {
      g_uart.DrainTx();
      g_reset_record.Set(pp::ResetCause::kUpdate);  // the image it boots says why it started
      mps2::SystemReset();
    }
  }
}

}  // namespace

extern "C" void Uart0Rx_Handler() { g_uart.OnRxInterrupt(); }

int main() {
  // The MPS2 has no analogue outputs of its own (the application models them), so there is no
  // safe code to write here; a real board's bootloader clears its DAC and valves first.
  const core::FlashLayout& layout = core::kDefaultLayout;
  static mps2::CodeFlash flash(layout.xip_base, layout.total, layout.sector_size);
  core::SlotImage slots[2];
  core::BootDecision d = core::Boot(flash, layout, kKind, slots);
  while (d.slot <= 1 && !VectorsPlausible(layout, d.slot, slots[d.slot])) {
    slots[d.slot].valid = false;  // a checked image that is not a program: choose again
    d = core::DecideBoot(core::BootStore(&flash, layout).Load(), slots);
  }
  if (d.slot <= 1) {
    Jump(layout.xip_base + layout.slot_offset[d.slot] + slots[d.slot].info.header_size);
  }
  static core::UpdateEngine engine(&flash, layout, kKind, core::kNoSlot);
  Recovery(engine, core::BootStore(&flash, layout).Load().rollback_floor);
}
