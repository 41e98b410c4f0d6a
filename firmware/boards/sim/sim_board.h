// The simulated board: firmware core + plant + simulated hal, on virtual time. Used by
// palpa-sim, and in-process by tests and benchmarks on free-running virtual time.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "flash_file.h"
#include "palpa/core/board.h"
#include "palpa/core/boot_state.h"
#include "palpa/core/update_engine.h"
#include "palpa/hal/byte_link.h"
#include "palpa/hal/clock.h"
#include "palpa/hal/digital_io.h"
#include "palpa/hal/fake/simulated_nor_flash.h"
#include "palpa/hal/linux/opened.h"
#include "palpa/hal/sim/plant.h"
#include "palpa/hal/sim/sim_io.h"

namespace palpa::sim {

struct SimBoardOptions {
  std::string config = "thesis-5finger";
  PlantOptions plant{};
  float time_scale = 1.0f;  ///< reported in Hello (palpa-sim --speed)
  uint32_t board_id = 1;
  uint32_t boot_nonce = 0;  ///< 0: derived from the seed
  /// Where the board's flash is kept between runs (palpa-sim --flash); empty: in memory only.
  std::string flash_file;
};

/// A valve driver held by a pulsing enable: it stays energised only while the line toggles.
class PulsedValve final : public hal::DigitalOutput {
 public:
  bool held(uint64_t now_us) const { return toggled_ && now_us - last_toggle_us_ <= 5000; }
  void set_now(uint64_t now_us) { now_us_ = now_us; }

 private:
  hal::Status DoSet(bool level) override {
    if (level != level_) {
      toggled_ = true;
      last_toggle_us_ = now_us_;
    }
    level_ = level;
    return hal::Status::kOk;
  }
  bool level_ = false;
  bool toggled_ = false;
  uint64_t last_toggle_us_ = 0;
  uint64_t now_us_ = 0;
};

class SimBoard {
 public:
  /// The board, or why not: an unknown configuration name (kBadValue, naming the known ones) or a
  /// flash file that cannot be used (FlashFile::Open's status and words).
  static hal::Opened<std::unique_ptr<SimBoard>> Create(const SimBoardOptions& options,
                                                       hal::ByteLink& link);

  /// Runs the plant and the board up to virtual time `us` (1 ms plant steps, a board loop pass
  /// at every step).
  void AdvanceTo(uint64_t us);
  void Advance(uint64_t us) { AdvanceTo(now_us_ + us); }
  /// One board loop pass at the current time (no tick falls due): serves what the host sent
  /// while virtual time is held.
  void Serve() { StepBoard(); }
  uint64_t now_us() const { return now_us_; }

  core::Board& board() { return *board_; }
  const core::Board& board() const { return *board_; }

  /// The board's flash (bootloader, two image slots, boot state, saved configuration) and what
  /// its last boot chose.
  hal::fake::SimulatedNorFlash& flash() { return *flash_; }
  const core::BootDecision& last_boot() const { return last_boot_; }
  uint32_t boots() const { return boots_; }
  /// Resets the board as a power cycle or a watchdog would: the bootloader chooses again.
  void Reset(protocol::ResetCause cause);

  /// Called after every 1 ms step (plant and board), with the virtual time: side channels sample
  /// here so that a stalled host process does not thin out their samples.
  void OnStep(std::function<void(uint64_t now_us)> callback) { on_step_ = std::move(callback); }

  /// The two latest-wins streams whose generations are stamped.
  enum class Stream : uint8_t { kSetpoints, kTargets };
  /// Called when a stream's new generation is applied (dac=false, at the dispatch) and when the
  /// DAC is first written with it (dac=true, at the next tick): the latency benchmarks' stamps,
  /// raw line setpoints and finger targets (what a scene sends) alike.
  void OnGeneration(std::function<void(Stream stream, uint32_t generation, bool dac)> callback) {
    stamp_ = std::move(callback);
  }
  Plant& plant() { return *plant_; }
  const Plant& plant() const { return *plant_; }
  bool pump_on() const { return pump_.level; }
  bool valves_held() const { return supply_.held(now_us_) && dump_.held(now_us_); }

 private:
  class VirtualClock final : public hal::Clock {
   public:
    uint64_t now_us = 0;

   private:
    uint64_t DoNowMicros() override { return now_us; }
  };
  class Pin final : public hal::DigitalOutput {
   public:
    bool level = false;

   private:
    hal::Status DoSet(bool value) override {
      level = value;
      return hal::Status::kOk;
    }
  };
  /// The lines' dump valve drivers: a set bit releases the line's valve (open).
  class VentPort final : public hal::DigitalPort {
   public:
    uint32_t bits = ~0u;

   private:
    uint8_t DoWrite(uint32_t value) override {
      bits = value;
      return kAllWritten;
    }
  };

  SimBoard() = default;

  uint64_t now_us_ = 0;
  uint64_t next_step_us_ = 1000;  ///< plant steps and board ticks sit on a 1 ms grid
  VirtualClock clock_;
  std::unique_ptr<Plant> plant_;
  std::unique_ptr<SimAnalogOutput> dac_;
  std::unique_ptr<SimAnalogInput> adc_;
  PulsedValve supply_, dump_;
  Pin pump_;
  VentPort vents_;
  std::unique_ptr<core::Board> board_;
  const core::BoardConfig* config_ = nullptr;
  hal::ByteLink* link_ = nullptr;
  core::BoardIdentity identity_{};
  std::unique_ptr<hal::fake::SimulatedNorFlash> flash_;
  std::unique_ptr<FlashFile> flash_file_;
  hal::Flash* storage_ = nullptr;  ///< what the board writes through: the flash, or its file
  std::unique_ptr<core::UpdateEngine> update_;
  core::BootDecision last_boot_{};
  uint32_t boots_ = 0;
  /// The bootloader's pass and the application's start on the chosen slot.
  void BootBoard(protocol::ResetCause cause);
  std::function<void(Stream, uint32_t, bool)> stamp_;
  std::function<void(uint64_t)> on_step_;
  /// Per stream: the generation last stamped applied, and whether its DAC write is still due.
  struct Stamped {
    uint32_t generation = 0;
    bool dac_pending = false;
  };
  Stamped stamped_[2];
  void StepBoard();
  void Stamp(Stream stream, uint32_t applied, bool ticked);
};

}  // namespace palpa::sim
