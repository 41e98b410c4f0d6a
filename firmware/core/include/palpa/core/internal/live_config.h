// Internal to firmware/core: the board's configuration — the live one, the candidate a change is
// validated in before it replaces the live one whole, the factory one, and the saved copies.
#pragma once

#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/core/config_store.h"
#include "palpa/hal/analog_output.h"

namespace palpa::core {

class LiveConfig {
 public:
  LiveConfig(const BoardConfig& factory, hal::Flash* flash, uint32_t flash_base,
             const hal::AnalogOutput& dac, LineCheck line_check)
      : factory_(factory), store_(flash, flash_base), dac_(dac), line_check_(line_check) {}

  /// At start: the saved configuration, or the factory one (also when the saved one was made for
  /// other hardware).
  void Load();

  const BoardConfig& live() const { return live_; }
  /// The live configuration's memory, for tests that corrupt it on purpose.
  BoardConfig& live_for_test() { return live_; }
  /// The factory configuration is live (nothing saved was loaded or committed since).
  bool is_default() const { return is_default_; }
  /// A saved copy is what the next boot loads.
  bool saved() const { return saved_; }
  /// The live configuration differs from what the next boot loads.
  bool unsaved() const { return unsaved_; }
  /// CRC of the live configuration's records (GetConfig reports it), once per configuration:
  /// computing it takes ≈ 15 000 instructions, too many to repeat for every chunk a host reads.
  uint32_t crc() const { return crc_; }

  /// The candidate, a copy of the live configuration, for a change to edit.
  BoardConfig& StartCandidate();
  /// Validates the candidate as a whole and makes it live, or leaves the live one untouched
  /// (the refusal's section and index in `detail`). Between two ticks: all at once.
  Status CommitCandidate(uint32_t& detail);
  Status Save();
  /// Erases the saved copies and makes the factory configuration live.
  Status FactoryReset();

 private:
  /// Every line's DAC resolution and signal range are what the board's DAC reports: a 16-bit
  /// line on a 12-bit DAC, or 4–20 mA on a 0–10 V output, would command the wrong pressure.
  /// And the board's own line check (BoardIo::line_check) accepts every line.
  bool FitsTheHardware(const BoardConfig& config, ConfigError* error) const;

  BoardConfig factory_;
  BoardConfig live_{};
  BoardConfig candidate_{};
  ConfigStore store_;
  const hal::AnalogOutput& dac_;
  LineCheck line_check_;
  bool is_default_ = true;
  bool saved_ = false;
  bool unsaved_ = false;
  uint32_t crc_ = 0;
};

}  // namespace palpa::core
