// libgpiod v1: one line requested for both edges' events, drained without blocking at each read.
#include "palpa/hal/linux/gpio_edge_input.h"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

#include "palpa/hal/linux/gpio_output.h"

namespace palpa::hal::linux_gpio {

std::unique_ptr<GpioEdgeInput> GpioEdgeInput::Open(const std::string& spec, bool active_high,
                                                   std::string* error) {
  gpiod_chip* chip = nullptr;
  gpiod_line* line = OpenLine(spec, &chip, error);
  if (line == nullptr) return nullptr;
  if (gpiod_line_request_both_edges_events(line, "palpa e-stop") != 0) {
    *error = "'" + spec + "': cannot watch the line's edges (" + std::strerror(errno) +
             "; is it used by another program?)";
    gpiod_chip_close(chip);
    return nullptr;
  }
  return std::unique_ptr<GpioEdgeInput>(new GpioEdgeInput(chip, line, active_high));
}

GpioEdgeInput::~GpioEdgeInput() {
  gpiod_line_release(line_);
  gpiod_chip_close(chip_);
}

bool GpioEdgeInput::DoRead() {
  bool pressed = false;
  const timespec now{0, 0};  // a poll: the tick never waits for the line
  for (int rounds = 0; rounds < 8; ++rounds) {
    const int ready = gpiod_line_event_wait(line_, &now);
    if (ready == 0) break;
    gpiod_line_event events[16];
    const int n = ready < 0 ? -1 : gpiod_line_event_read_multiple(line_, events, 16);
    if (n <= 0) {
      failed_ = true;
      break;
    }
    for (int i = 0; i < n; ++i) {
      const bool high = events[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE;
      if (high == active_high_) {
        pressed = true;  // however soon it was released again
        ++active_edges_;
      }
    }
  }
  // The level too: an edge lost to a full kernel queue must not hide a press that lasts.
  const int level = gpiod_line_get_value(line_);
  if (level < 0) failed_ = true;
  return failed_ || pressed || (level == 1) == active_high_;
}

}  // namespace palpa::hal::linux_gpio
