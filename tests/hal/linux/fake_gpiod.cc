// The fake libgpiod: the six v1 functions GpioOutput uses.
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

void gpiod_line_release(gpiod_line* line) { fg::state().log.push_back("release " + line->Name()); }

}  // extern "C"
