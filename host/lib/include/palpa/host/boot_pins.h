// Reset and boot pins for boards whose application cannot take an update (it does not start, or
// it is not palpa's): hold the boot pin and pulse reset to start the bootloader's recovery mode,
// release the boot pin before the reboot into the new image. The pins are any DigitalOutput
// (GPIO lines through libgpiod on a Linux host).
#pragma once

#include <functional>

#include "palpa/hal/digital_io.h"

namespace palpa::host {

class BootPins {
 public:
  /// `reset` is active low (nRST), `boot` active high (BOOT0-style); either may be nullptr.
  /// `sleep_ms` waits (the tests' seam for time).
  BootPins(hal::DigitalOutput* reset, hal::DigitalOutput* boot, std::function<void(int)> sleep_ms);

  static constexpr int kResetPulseMs = 50;  ///< held in reset: longer than any supervisor's filter
  static constexpr int kStartMs = 200;      ///< after reset, before the bootloader listens

  /// Boot pin asserted, reset pulsed: the board starts in its bootloader's recovery mode.
  void ResetIntoBootloader();
  /// Boot pin released: the next reset (UpdateReboot or a pulse) runs the application.
  void ReleaseBoot();
  /// Boot pin released, reset pulsed.
  void ResetIntoApplication();

 private:
  void PulseReset();
  hal::DigitalOutput* reset_;
  hal::DigitalOutput* boot_;
  std::function<void(int)> sleep_ms_;
};

}  // namespace palpa::host
