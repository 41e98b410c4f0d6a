// The simulated update, with and without power cuts.
#include "update_scenario.h"

#include <random>

namespace palpa::testing {
namespace pp = protocol;

host::UpdatePackage MakeRelease(uint8_t major, uint8_t minor, uint32_t rollback_counter,
                                uint32_t body_size, uint32_t seed, pp::BoardKind kind,
                                pp::ImageSigner* signer) {
  std::mt19937 rng(seed * 977u + major * 31u + minor);
  std::vector<uint8_t> body(body_size);
  for (uint8_t& b : body) b = static_cast<uint8_t>(rng());
  host::UpdatePackage p;
  for (uint8_t slot = 0; slot < 2; ++slot) {
    host::ImageSpec spec;
    spec.body = body;
    spec.load_address = core::kDefaultLayout.xip_base + core::kDefaultLayout.slot_offset[slot];
    spec.version_major = major;
    spec.version_minor = minor;
    spec.board_kind = kind;
    spec.slot = slot;
    spec.rollback_counter = rollback_counter;
    spec.signer = signer;
    p.slot_image[slot] = host::BuildImage(spec);
  }
  return p;
}

UpdateWorld::UpdateWorld(uint32_t seed)
    : flash(core::kDefaultLayout.total, core::kDefaultLayout.sector_size, seed) {
  const host::UpdatePackage factory = MakeRelease(1, 0, 1, 40 * 1024, seed);
  const std::vector<uint8_t>& image = factory.slot_image[0];
  flash.Program(layout.slot_offset[0], image.data(), image.size());
  Reboot();
}

core::BootDecision UpdateWorld::Reboot() {
  core::SlotImage slots[2];
  last_boot = core::Boot(flash, layout, kind, slots);
  running = last_boot.slot;
  return last_boot;
}

UpdateOutcome RunUpdate(UpdateWorld& w, const host::UpdatePackage& release, bool confirm,
                        hal::Watchdog* watchdog, hal::Flash* engine_flash) {
  UpdateOutcome out;
  auto failed = [&](const char* step) {
    out.failed_step = step;
    return out;
  };
  hal::Flash* flash = engine_flash != nullptr ? engine_flash : &w.flash;
  core::UpdateEngine engine(flash, w.layout, w.kind, w.running, watchdog);
  const uint8_t slot = engine.inactive_slot();
  const std::vector<uint8_t>& image = release.slot_image[slot];
  const auto size = static_cast<uint32_t>(image.size());
  uint32_t detail = 0;
  if (engine.Enter({slot, size}, &detail) != pp::Status::kOk) return failed("enter");
  const uint32_t sector = w.layout.sector_size;
  if (engine.Erase({slot, 0, (size + sector - 1) / sector * sector}, &detail) != pp::Status::kOk)
    return failed("erase");
  for (uint32_t at = 0; at < size; at += pp::kMaxUpdateChunk) {
    pp::UpdateWrite m;
    m.slot = slot;
    m.offset = at;
    m.data_size = static_cast<uint8_t>(std::min<uint32_t>(pp::kMaxUpdateChunk, size - at));
    std::copy(image.begin() + at, image.begin() + at + m.data_size, m.data.begin());
    if (engine.Write(m, &detail) != pp::Status::kOk) return failed("write");
  }
  const pp::Sha256Digest digest = pp::Sha256Of(image.data(), image.size());
  if (engine.Query(slot).written_sha256 != digest) return failed("hash");
  if (engine.Activate({slot, size, digest}, &detail) != pp::Status::kOk) return failed("activate");
  const core::BootDecision trial = w.Reboot();
  if (!w.flash.powered() || trial.reason != core::BootReason::kTrial) return failed("trial boot");
  if (!confirm) {
    out.completed = true;
    return out;
  }
  core::UpdateEngine running(flash, w.layout, w.kind, w.running, watchdog);
  if (running.Confirm({w.running}, &detail) != pp::Status::kOk) return failed("confirm");
  out.completed = true;
  return out;
}

CutOutcome CutPowerDuringUpdate(uint64_t cut_after, uint32_t seed) {
  UpdateWorld w(seed);
  const host::UpdatePackage release = MakeRelease(1, 1, 2, 40 * 1024, seed + 1);
  w.flash.CutPowerAfter(static_cast<uint32_t>(cut_after));
  const UpdateOutcome update = RunUpdate(w, release);
  CutOutcome out;
  out.phase = update.completed ? "after confirm" : update.failed_step;
  w.flash.PowerOn();
  const core::BootDecision d = w.Reboot();
  out.reason = d.reason;
  if (d.slot > 1) return out;
  const core::SlotImage booted = core::InspectSlot(w.flash, w.layout, d.slot, w.kind);
  out.valid = booted.valid;
  out.is_new = booted.info.version_minor == 1;
  return out;
}

uint64_t UpdateFlashBytes(uint32_t seed) {
  UpdateWorld w(seed);
  const uint64_t before = w.flash.bytes_touched();
  RunUpdate(w, MakeRelease(1, 1, 2, 40 * 1024, seed + 1));
  return w.flash.bytes_touched() - before;
}

}  // namespace palpa::testing
