// A GPIO input line on Linux through libgpiod (v1 API) with edge events: the E-stop. A press
// shorter than a tick is still seen (its edge waits in the kernel's queue); reading never blocks.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "palpa/hal/digital_io.h"

struct gpiod_chip;
struct gpiod_line;

namespace palpa::hal::linux_gpio {

class GpioEdgeInput final : public DigitalInput {
 public:
  /// "CHIP:LINE" as GpioOutput takes it. Requests both edges' events; `active_high`: the level
  /// that asserts the input (an E-stop's normally-closed contact to ground reads high when
  /// pressed or when its wire breaks). nullptr with *error naming the chip, the line and why.
  static std::unique_ptr<GpioEdgeInput> Open(const std::string& spec, bool active_high,
                                             std::string* error);
  ~GpioEdgeInput();
  GpioEdgeInput(const GpioEdgeInput&) = delete;
  GpioEdgeInput& operator=(const GpioEdgeInput&) = delete;

  uint32_t active_edges() const { return active_edges_; }  ///< edges to the active level so far
  bool failed() const { return failed_; }  ///< a read failed: the input reads asserted from then

 private:
  GpioEdgeInput(gpiod_chip* chip, gpiod_line* line, bool active_high)
      : chip_(chip), line_(line), active_high_(active_high) {}
  /// Asserted when an edge to the active level came since the last read (however short the
  /// press), when the line is at the active level now, or when it cannot be read.
  bool DoRead() override;
  gpiod_chip* chip_;
  gpiod_line* line_;
  bool active_high_;
  bool failed_ = false;
  uint32_t active_edges_ = 0;
};

}  // namespace palpa::hal::linux_gpio
