// The simulated board's wiring and its virtual-time loop.
#include "sim_board.h"

#include "palpa/core/board_configs.h"

namespace palpa::sim {

std::unique_ptr<SimBoard> SimBoard::Create(const SimBoardOptions& options, hal::ByteLink& link,
                                           std::string* error) {
  const core::BoardConfig* config = core::FindBoardConfig(options.config.c_str());
  if (config == nullptr) {
    if (error != nullptr) {
      *error = "unknown board configuration '" + options.config + "' (known:";
      for (uint8_t i = 0; i < core::kBoardConfigCount; ++i)
        *error += std::string(" ") + core::kBoardConfigs[i].name;
      *error += ")";
    }
    return nullptr;
  }
  std::unique_ptr<SimBoard> sim(new SimBoard());
  sim->plant_ =
      std::make_unique<Plant>(config->lines.data(), config->line_count, config->fingers.data(),
                              config->finger_count, options.plant);
  sim->dac_ = std::make_unique<SimAnalogOutput>(*sim->plant_);
  sim->adc_ = std::make_unique<SimAnalogInput>(*sim->plant_);
  core::BoardIdentity id;
  id.kind = protocol::BoardKind::kSim;
  id.board_id = options.board_id;
  id.plant_simulated = true;
  id.time_scale = options.time_scale;
  id.boot_nonce =
      options.boot_nonce != 0 ? options.boot_nonce : options.plant.seed * 2246822519u + 0x5EED;
  id.rx_buffer_bytes = 4096;
  core::BoardIo io{sim->clock_, *sim->dac_, sim->adc_.get(), sim->supply_,
                   sim->dump_,  sim->pump_, nullptr,         link,
                   nullptr,     0};
  sim->board_ = std::make_unique<core::Board>(*config, io, id);
  sim->board_->Start();
  return sim;
}

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
  if (!stamp_) return;
  // A tick writes the DAC before the link is served: a generation applied by this pass's
  // dispatch reaches the DAC on the next tick.
  if (ticked && dac_pending_) {
    dac_pending_ = false;
    stamp_(stamped_generation_, true);
  }
  const uint32_t applied = board_->applied_setpoint_generation();
  if (applied != stamped_generation_) {
    stamped_generation_ = applied;
    dac_pending_ = true;
    stamp_(applied, false);
  }
}

}  // namespace palpa::sim
