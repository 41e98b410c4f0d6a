// A GPIO input line with edge events on Linux through libgpiod (v1 API): the E-stop, read each tick
// without blocking; a press shorter than a tick is still seen (its edges wait in the kernel).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "palpa/hal/digital_io.h"
#include "palpa/hal/linux/opened.h"

struct gpiod_chip;
struct gpiod_line;

namespace palpa::hal::linux_gpio {

struct GpioEdge {
  bool active;           ///< the line's level after the edge: true = asserted
  int64_t timestamp_ns;  ///< when the kernel saw the edge (CLOCK_MONOTONIC)
};

class GpioEdgeInput final : public DigitalInput {
 public:
  /// "CHIP:LINE" as for GpioOutput. Requests the line as an input with both edges reported;
  /// `active_low`: asserted while the line is low (a pulled-up line an E-stop pulls to ground);
  /// false for an E-stop's normally-closed contact to ground, which reads high when pressed or
  /// when its wire breaks. A failure names the chip, the line and the reason, with GpioOutput's
  /// statuses: kBadValue, kNotFound, kIoError (the kernel refused to watch the line).
  static Opened<std::unique_ptr<GpioEdgeInput>> Open(const std::string& spec, bool active_low);
  ~GpioEdgeInput();
  GpioEdgeInput(const GpioEdgeInput&) = delete;
  GpioEdgeInput& operator=(const GpioEdgeInput&) = delete;

  /// The edges the kernel queued since the last call, oldest first, at most `max` (the rest stay
  /// queued for the next call). Never blocks: 0 when there are none. -1 when the read failed
  /// (error() says why). Read() drains the same queue: use one or the other.
  int ReadEvents(GpioEdge* edges, int max);
  /// The line's level now: true = asserted. true also, with error() set, when the read failed: an
  /// E-stop that cannot be read counts as pressed.
  bool active();
  /// Why a read failed, the first time one did; empty while none has. Once set, Read() is asserted
  /// for good: a line that failed once is not trusted again.
  const std::string& error() const { return error_; }

 private:
  GpioEdgeInput(std::string spec, gpiod_chip* chip, gpiod_line* line, int fd)
      : spec_(std::move(spec)), chip_(chip), line_(line), fd_(fd) {}
  /// The DigitalInput the board's tick reads, a latch: drains the queued edges without blocking;
  /// asserted when one of them went to the active level or two or more came (however soon the
  /// line came back), when the level is active now (a press whose edge a full queue lost), or when
  /// a read ever failed.
  bool DoRead() override;
  void Fail(const char* what);
  std::string spec_;
  gpiod_chip* chip_;
  gpiod_line* line_;
  int fd_;  // the line's event file, non-blocking
  std::string error_;
};

}  // namespace palpa::hal::linux_gpio
