// The fake libgpiod: the v1 functions GpioOutput and GpioEdgeInput use.
#include "fake_gpiod.h"

#include <fcntl.h>
#include <gpiod.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <map>
#include <memory>

namespace palpa::testing::fake_gpiod {
State& state() {
  static State s;
  return s;
}
void Reset() { state() = State{}; }
volatile std::sig_atomic_t unwritable_armed = 1;
}  // namespace palpa::testing::fake_gpiod

namespace fg = palpa::testing::fake_gpiod;

struct gpiod_chip {
  std::string name;
  std::map<unsigned, std::unique_ptr<gpiod_line>> lines;
};
struct gpiod_line {
  gpiod_chip* chip;
  unsigned offset;
  bool active_low = false;
  int event_fd = -1;  ///< requested for edge events: an eventfd standing in for the kernel's file
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
  for (auto& [offset, line] : chip->lines) std::erase(fg::state().event_lines, line.get());
  delete chip;
}

gpiod_line* gpiod_chip_get_line(gpiod_chip* chip, unsigned int offset) {
  if (offset >= fg::state().lines_per_chip) {
    errno = EINVAL;
    return nullptr;
  }
  auto& line = chip->lines[offset];
  if (!line) {
    line.reset(new gpiod_line{chip, offset});
    fg::state().event_lines.push_back(line.get());
  }
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
  if (fg::unwritable_armed && fg::state().unwritable.count(line->Name())) {
    fg::state().log.push_back("failed set " + line->Name() + "=" + std::to_string(value));
    errno = EIO;
    return -1;
  }
  fg::state().log.push_back("set " + line->Name() + "=" + std::to_string(value));
  return 0;
}

int gpiod_line_request_both_edges_events_flags(gpiod_line* line, const char*, int flags) {
  if (fg::state().busy.count(line->Name())) {
    errno = EBUSY;
    return -1;
  }
  line->active_low = (flags & GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW) != 0;
  line->event_fd = eventfd(0, 0);  // a real file, so the caller's fcntl acts on something
  fg::state().log.push_back("events " + line->Name() + (line->active_low ? " active-low" : ""));
  return 0;
}

int gpiod_line_event_get_fd(gpiod_line* line) { return line->event_fd; }

// The kernel reports values and edges in the line's sense: an active-low line's level inverted.
int gpiod_line_get_value(gpiod_line* line) {
  if (fg::state().broken.count(line->Name())) {
    errno = EIO;
    return -1;
  }
  return fg::state().levels[line->Name()] ^ (line->active_low ? 1 : 0);
}

int gpiod_line_event_read_fd_multiple(int fd, gpiod_line_event* events, unsigned n) {
  gpiod_line* line = nullptr;
  for (gpiod_line* l : fg::state().event_lines)
    if (l->event_fd == fd) line = l;
  if (line == nullptr) {
    errno = EBADF;
    return -1;
  }
  if (fg::state().broken.count(line->Name())) {
    errno = EIO;
    return -1;
  }
  auto& queue = fg::state().edges[line->Name()];
  if (queue.empty()) {
    // The real read waits for the next edge unless the file is non-blocking: the tick would hang.
    errno = (fcntl(fd, F_GETFL) & O_NONBLOCK) ? EAGAIN : EDEADLK;
    return -1;
  }
  unsigned i = 0;
  for (; i < n && !queue.empty(); ++i, queue.pop_front()) {
    events[i] = gpiod_line_event{};
    events[i].event_type = queue.front() != line->active_low ? GPIOD_LINE_EVENT_RISING_EDGE
                                                             : GPIOD_LINE_EVENT_FALLING_EDGE;
  }
  return static_cast<int>(i);
}

void gpiod_line_release(gpiod_line* line) {
  if (line->event_fd >= 0) close(line->event_fd);
  line->event_fd = -1;
  fg::state().log.push_back("release " + line->Name());
}

}  // extern "C"
