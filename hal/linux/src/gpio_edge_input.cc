// libgpiod v1: one line requested as an input with both edges; its event file read non-blocking.
#include "palpa/hal/linux/gpio_edge_input.h"

#include <fcntl.h>
#include <gpiod.h>

#include <cerrno>
#include <cstring>

#include "gpio_line.h"

namespace palpa::hal::linux_gpio {

Opened<std::unique_ptr<GpioEdgeInput>> GpioEdgeInput::Open(const std::string& spec,
                                                           bool active_low) {
  auto found = FindGpioLine(spec);
  if (!found.ok()) return {found.status, found.message};
  gpiod_chip* chip = found.value.chip;
  gpiod_line* line = found.value.line;
  // The flag makes the kernel report levels and edges as asserted/released, not as high/low.
  const int flags = active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
  if (gpiod_line_request_both_edges_events_flags(line, "palpa", flags) != 0) {
    const std::string why = "'" + spec + "': cannot watch the line's edges (" +
                            std::strerror(errno) +
                            "; is it used by another program, or can the chip not interrupt?)";
    gpiod_chip_close(chip);
    return {Status::kIoError, why};
  }
  const int fd = gpiod_line_event_get_fd(line);
  // Non-blocking: the tick reads what is queued and never waits for an edge.
  if (fd < 0 || fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK) != 0) {
    const std::string why = "'" + spec + "': cannot make the line's event file non-blocking (" +
                            std::strerror(errno) + ")";
    gpiod_line_release(line);
    gpiod_chip_close(chip);
    return {Status::kIoError, why};
  }
  return std::unique_ptr<GpioEdgeInput>(new GpioEdgeInput(spec, chip, line, fd));
}

GpioEdgeInput::~GpioEdgeInput() {
  gpiod_line_release(line_);
  gpiod_chip_close(chip_);
}

int GpioEdgeInput::ReadEvents(GpioEdge* edges, int max) {
  constexpr int kBatch = 16;
  gpiod_line_event events[kBatch];
  int count = 0;
  while (count < max) {
    const int want = max - count < kBatch ? max - count : kBatch;
    const int got = gpiod_line_event_read_fd_multiple(fd_, events, static_cast<unsigned>(want));
    if (got < 0) {
      if (errno == EAGAIN) break;  // nothing more queued
      Fail("reading the line's edges");
      return -1;
    }
    for (int i = 0; i < got; ++i) {
      edges[count + i].active = events[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE;
      edges[count + i].timestamp_ns =
          static_cast<int64_t>(events[i].ts.tv_sec) * 1000000000 + events[i].ts.tv_nsec;
    }
    count += got;
    if (got < want) break;
  }
  return count;
}

bool GpioEdgeInput::active() {
  const int value = gpiod_line_get_value(line_);
  if (value < 0) {
    Fail("reading the line");
    return true;
  }
  return value == 1;
}

bool GpioEdgeInput::DoRead() {
  constexpr int kMax = 16;  // the kernel's queue per line (v1 uAPI)
  GpioEdge edges[kMax];
  bool pressed = false;
  int count = 0;
  // Bounded: a line chattering faster than this drains leaves the rest to the next tick, whose
  // level read covers the press meanwhile.
  for (int round = 0; round < 4; ++round) {
    const int n = ReadEvents(edges, kMax);
    for (int i = 0; i < n; ++i) pressed |= edges[i].active;  // however soon it was released
    count += n > 0 ? n : 0;
    if (n < kMax) break;
  }
  // Two edges mean the line was at the other level between them: from released, a press. The v1
  // uAPI stamps an edge with the level when its interrupt is handled, so a press shorter than
  // that reads as two releases.
  pressed |= count >= 2;
  const bool level = active();
  return !error_.empty() || pressed || level;
}

void GpioEdgeInput::Fail(const char* what) {
  if (error_.empty())  // the first failure is the one that explains the rest
    error_ = "'" + spec_ + "': " + what + " failed (" + std::strerror(errno) + ")";
}

}  // namespace palpa::hal::linux_gpio
