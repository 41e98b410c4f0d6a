// The simulated board's wiring and its virtual-time loop.
#include "sim_board.h"

#include "palpa/core/board_configs.h"
#include "palpa/hal/linux/ed25519_signer.h"
#include "palpa/keys/development_keys.h"

namespace palpa::sim {

hal::Opened<std::unique_ptr<SimBoard>> SimBoard::Create(const SimBoardOptions& options,
                                                        hal::ByteLink& link) {
  const core::BoardConfig* config = core::FindBoardConfig(options.config.c_str());
  if (config == nullptr) {
    std::string known;
    for (uint8_t i = 0; i < core::kBoardConfigCount; ++i)
      known += std::string(" ") + core::kBoardConfigs[i].name;
    return {Status::kBadValue,
            "--config " + options.config + ": unknown board configuration (known:" + known + ")"};
  }
  std::unique_ptr<SimBoard> sim(new SimBoard());
  sim->plant_ =
      std::make_unique<Plant>(config->lines.data(), config->line_count, config->fingers.data(),
                              config->finger_count, options.plant);
  sim->dac_ = std::make_unique<SimAnalogOutput>(*sim->plant_);
  sim->adc_ = std::make_unique<SimAnalogInput>(*sim->plant_);
  core::BoardIdentity& id = sim->identity_;
  id.kind = protocol::BoardKind::kSim;
  id.board_id = options.board_id;
  id.plant_simulated = true;
  id.time_scale = options.time_scale;
  id.boot_nonce =
      options.boot_nonce != 0 ? options.boot_nonce : options.plant.seed * 2246822519u + 0x5EED;
  id.rx_buffer_bytes = 4096;
  sim->config_ = config;
  sim->link_ = &link;
  // The flash as it leaves the factory: this build's image in slot 0 (the body stands in for
  // the code: nothing executes it here), the bootloader's first pass still to come.
  const core::FlashLayout& layout = core::kDefaultLayout;
  sim->flash_ = std::make_unique<hal::fake::SimulatedNorFlash>(layout.total, layout.sector_size,
                                                               options.plant.seed);
  static const char kBody[] = "palpa-sim application image";
  protocol::ImageFields f;
  f.load_address = layout.xip_base + layout.slot_offset[0];
  f.version_major = id.firmware_major;
  f.version_minor = id.firmware_minor;
  f.version_revision = id.firmware_patch;
  f.board_kind = protocol::BoardKind::kSim;
  f.slot = 0;
  f.rollback_counter = 1;
  uint8_t image[protocol::ImageSize(sizeof(kBody))];
  hal::linux_signing::Ed25519Signer factory_key(keys::DevelopmentSeed());  // DEVELOPMENT ONLY
  const uint32_t size = protocol::WriteImage(f, reinterpret_cast<const uint8_t*>(kBody),
                                             sizeof(kBody), image, sizeof(image), &factory_key);
  sim->flash_->Program(layout.slot_offset[0], image, size);
  sim->storage_ = sim->flash_.get();
  if (!options.flash_file.empty()) {  // the flash as the last run left it, kept from now on
    sim->flash_file_ = std::make_unique<FlashFile>(*sim->flash_);
    const hal::Done kept = sim->flash_file_->Open(options.flash_file, options.config);
    if (!kept.ok()) return {kept.status, kept.message};
    sim->storage_ = sim->flash_file_.get();
  }
  sim->BootBoard(protocol::ResetCause::kPowerOn);
  return sim;
}

void SimBoard::BootBoard(protocol::ResetCause cause) {
  const core::FlashLayout& layout = core::kDefaultLayout;
  core::SlotImage slots[2];
  last_boot_ = core::Boot(*storage_, layout, protocol::BoardKind::kSim, slots);
  ++boots_;
  core::BoardIdentity id = identity_;
  id.reset_cause = cause;
  id.boot_nonce = identity_.boot_nonce + 0x9E3779B9u * (boots_ - 1);  // a new nonce per boot
  id.recovery = last_boot_.slot > 1;
  if (!id.recovery) {
    const protocol::ImageInfo& info = slots[last_boot_.slot].info;
    id.firmware_major = info.version_major;
    id.firmware_minor = info.version_minor;
    id.firmware_patch = static_cast<uint8_t>(info.version_revision);
    id.active_slot = last_boot_.slot;
  }
  id.rollback_counter = core::BootStore(storage_, layout).Load().rollback_floor;
  update_ = std::make_unique<core::UpdateEngine>(storage_, layout, protocol::BoardKind::kSim,
                                                 last_boot_.slot);
  if (id.recovery) id.active_slot = static_cast<uint8_t>(1 - update_->inactive_slot());
  vents_.bits = ~0u;  // a reset releases every line's valve driver until the board writes them
  // The configuration is saved where a real board keeps it: two sectors of the same flash.
  core::BoardIo io{clock_, *dac_,    adc_.get(),           supply_,       dump_,  pump_, nullptr,
                   *link_, storage_, layout.config_offset, update_.get(), &vents_};
  board_ = std::make_unique<core::Board>(*config_, io, id);
  board_->Start();
}

void SimBoard::Reset(protocol::ResetCause cause) { BootBoard(cause); }

void SimBoard::AdvanceTo(uint64_t us) {
  constexpr uint64_t kStepUs = 1000;
  while (next_step_us_ <= us) {
    now_us_ = next_step_us_;
    next_step_us_ += kStepUs;
    clock_.now_us = now_us_;
    supply_.set_now(now_us_);
    dump_.set_now(now_us_);
    // Critical for safety, modelled: without both valves held the chambers vent.
    plant_->SetVented(!valves_held());
    plant_->SetLineVents(vents_.bits);
    plant_->Step();
    StepBoard();
    if (on_step_) on_step_(now_us_);
  }
  if (us > now_us_) {  // between steps: serve the link without a tick
    now_us_ = us;
    clock_.now_us = now_us_;
    StepBoard();
  }
}

void SimBoard::StepBoard() {
  const bool ticked = board_->Step();
  if (board_->reboot_requested()) {  // UpdateReboot's Ack went out with this pass's flush
    BootBoard(protocol::ResetCause::kUpdate);
    return;
  }
  if (!stamp_) return;
  Stamp(Stream::kSetpoints, board_->applied_setpoint_generation(), ticked);
  Stamp(Stream::kTargets, board_->applied_target_generation(), ticked);
}

void SimBoard::Stamp(Stream stream, uint32_t applied, bool ticked) {
  Stamped& s = stamped_[static_cast<size_t>(stream)];
  // A tick writes the DAC before the link is served: a generation applied by this pass's
  // dispatch reaches the DAC on the next tick.
  if (ticked && s.dac_pending) {
    s.dac_pending = false;
    stamp_(stream, s.generation, true);
  }
  if (applied != s.generation) {
    s.generation = applied;
    s.dac_pending = true;
    stamp_(stream, applied, false);
  }
}

}  // namespace palpa::sim
