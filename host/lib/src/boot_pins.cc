// Reset and boot pin sequences.
#include "palpa/host/boot_pins.h"

namespace palpa::host {

BootPins::BootPins(hal::DigitalOutput* reset, hal::DigitalOutput* boot,
                   std::function<void(int)> sleep_ms)
    : reset_(reset), boot_(boot), sleep_ms_(std::move(sleep_ms)) {}

void BootPins::PulseReset() {
  if (reset_ == nullptr) return;
  reset_->Set(false);
  sleep_ms_(kResetPulseMs);
  reset_->Set(true);
  sleep_ms_(kStartMs);
}

void BootPins::ResetIntoBootloader() {
  if (boot_ != nullptr) boot_->Set(true);  // sampled by the bootloader as it starts
  PulseReset();
}

void BootPins::ReleaseBoot() {
  if (boot_ != nullptr) boot_->Set(false);
}

void BootPins::ResetIntoApplication() {
  ReleaseBoot();
  PulseReset();
}

}  // namespace palpa::host
