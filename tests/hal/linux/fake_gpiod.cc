// The fake libgpiod: the v1 functions GpioOutput and GpioEdgeInput use.
#include "fake_gpiod.h"

#include <gpiod.h>

#include <cerrno>
#include <map>
#include <memory>

namespace palpa::testing::fake_gpiod {
State& state() {
  static State s;
  return s;
}
void Reset() { state() = State{}; }
}  // namespace palpa::testing::fake_gpiod

namespace fg = palpa::testing::fake_gpiod;

struct gpiod_chip {
  std::string name;
  std::map<unsigned, std::unique_ptr<gpiod_line>> lines;
};
struct gpiod_line {
  gpiod_chip* chip;
  unsigned offset;
  std::string Name() const { return chip->name + ":" + std::to_string(offset); }
};

extern "C" {

gpiod_chip* gpiod_chip_open_lookup(const char* descr) {
  std::string name = descr;
  if (!name.empty() && name.find_first_not_of("0123456789") == std::string::npos)
    name = "gpiochip" + name;
  if (!fg::state().chips.count(name)) {
    errno = ENOENT;
    return nullptr;
  }
  ++fg::state().open_chips;
  return new gpiod_chip{name, {}};
}

void gpiod_chip_close(gpiod_chip* chip) {
  --fg::state().open_chips;
  delete chip;
}

gpiod_line* gpiod_chip_get_line(gpiod_chip* chip, unsigned int offset) {
  if (offset >= fg::state().lines_per_chip) {
    errno = EINVAL;
    return nullptr;
  }
  auto& line = chip->lines[offset];
  if (!line) line.reset(new gpiod_line{chip, offset});
  return line.get();
}

int gpiod_line_request_output(gpiod_line* line, const char*, int default_val) {
  if (fg::state().busy.count(line->Name())) {
    errno = EBUSY;
    return -1;
  }
  fg::state().log.push_back("request " + line->Name() + "=" + std::to_string(default_val));
  return 0;
}

int gpiod_line_set_value(gpiod_line* line, int value) {
  fg::state().log.push_back("set " + line->Name() + "=" + std::to_string(value));
  return 0;
}

int gpiod_line_request_both_edges_events(gpiod_line* line, const char*) {
  if (fg::state().busy.count(line->Name())) {
    errno = EBUSY;
    return -1;
  }
  fg::state().log.push_back("events " + line->Name());
  return 0;
}

int gpiod_line_get_value(gpiod_line* line) {
  if (fg::state().broken.count(line->Name())) {
    errno = EIO;
    return -1;
  }
  return fg::state().levels[line->Name()];
}

int gpiod_line_event_wait(gpiod_line* line, const timespec* timeout) {
  if (timeout == nullptr || timeout->tv_sec != 0 || timeout->tv_nsec != 0) return -1;  // blocks
  if (fg::state().broken.count(line->Name())) {
    errno = EIO;
    return -1;
  }
  return fg::state().edges[line->Name()].empty() ? 0 : 1;
}

int gpiod_line_event_read_multiple(gpiod_line* line, gpiod_line_event* events, unsigned n) {
  auto& queue = fg::state().edges[line->Name()];
  unsigned i = 0;
  for (; i < n && !queue.empty(); ++i, queue.pop_front())
    events[i].event_type =
        queue.front() ? GPIOD_LINE_EVENT_RISING_EDGE : GPIOD_LINE_EVENT_FALLING_EDGE;
  return static_cast<int>(i);
}

void gpiod_line_release(gpiod_line* line) { fg::state().log.push_back("release " + line->Name()); }

}  // extern "C"
