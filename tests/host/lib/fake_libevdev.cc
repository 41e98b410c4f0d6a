// The link-time fake of libevdev: replays a recorded script, keeping the device's state and the
// reader's apart so that events the kernel dropped are seen only through the resync.
#include "fake_libevdev.h"

#include <libevdev/libevdev.h>

#include <cerrno>
#include <cmath>
#include <utility>

namespace palpa::testing {

FakeEvdev& Evdev() {
  static FakeEvdev fake;
  return fake;
}

void ResetEvdev() {
  FakeEvdev fresh;  // swapped, so what the test allocated is freed with it
  std::swap(Evdev(), fresh);
}

input_event Ev(double t, unsigned type, unsigned code, int value) {
  input_event e{};
  e.time.tv_sec = static_cast<time_t>(std::floor(t));
  e.time.tv_usec = static_cast<suseconds_t>(std::lround((t - std::floor(t)) * 1e6));
  e.type = static_cast<__u16>(type);
  e.code = static_cast<__u16>(code);
  e.value = value;
  return e;
}

void MakeTablet() {
  FakeEvdev& f = Evdev();
  f.abs[{EV_ABS, ABS_X}] = input_absinfo{0, 0, 15200, 0, 0, 100};
  f.abs[{EV_ABS, ABS_Y}] = input_absinfo{0, 0, 9500, 0, 0, 100};
  f.abs[{EV_ABS, ABS_PRESSURE}] = input_absinfo{0, 0, 2047, 0, 0, 0};
  f.codes.push_back({EV_KEY, BTN_TOUCH});
}

void Report(double t, int x, int y, int pressure, bool touch) {
  for (const input_event& e :
       {Ev(t, EV_ABS, ABS_X, x), Ev(t, EV_ABS, ABS_Y, y), Ev(t, EV_ABS, ABS_PRESSURE, pressure),
        Ev(t, EV_KEY, BTN_TOUCH, touch ? 1 : 0), Ev(t, EV_SYN, SYN_REPORT, 0)}) {
    Evdev().script.push_back({EvdevStep::kEvent, e, {}});
  }
}

}  // namespace palpa::testing

using palpa::testing::Evdev;

struct libevdev {
  int unused;
};

namespace {
libevdev the_device;

bool Has(unsigned type, unsigned code) {
  if (type == EV_ABS) return Evdev().abs.count({type, code}) > 0;
  for (const auto& c : Evdev().codes)
    if (c.first == type && c.second == code) return true;
  return false;
}

void Apply(std::map<std::pair<unsigned, unsigned>, int>& state, const input_event& e) {
  if (e.type != EV_SYN) state[{e.type, e.code}] = e.value;
}
}  // namespace

extern "C" {

int libevdev_new_from_fd(int, libevdev** dev) {
  if (!Evdev().evdev) return -ENOTTY;
  *dev = &the_device;
  return 0;
}

void libevdev_free(libevdev* dev) {
  if (dev != nullptr) Evdev().freed = true;
}

const char* libevdev_get_name(const libevdev*) { return Evdev().name.c_str(); }

int libevdev_has_event_code(const libevdev*, unsigned int type, unsigned int code) {
  return Has(type, code) ? 1 : 0;
}

const input_absinfo* libevdev_get_abs_info(const libevdev*, unsigned int code) {
  const auto a = Evdev().abs.find({EV_ABS, code});
  return a == Evdev().abs.end() ? nullptr : &a->second;
}

int libevdev_set_clock_id(libevdev*, int clock_id) {
  Evdev().clock_id = clock_id;
  return 0;
}

int libevdev_get_event_value(const libevdev*, unsigned int type, unsigned int code) {
  if (!Has(type, code)) return 0;
  const auto v = Evdev().reader_state.find({type, code});
  if (v != Evdev().reader_state.end()) return v->second;
  if (type == EV_ABS) return Evdev().abs.at({type, code}).value;
  return 0;
}

int libevdev_next_event(libevdev*, unsigned int flags, input_event* ev) {
  auto& f = Evdev();
  if (flags & LIBEVDEV_READ_FLAG_SYNC) {
    if (!f.syncing) return -EAGAIN;
    if (f.pending_sync.empty()) {
      f.syncing = false;
      return -EAGAIN;
    }
    *ev = f.pending_sync.front();
    f.pending_sync.erase(f.pending_sync.begin());
    Apply(f.reader_state, *ev);
    return LIBEVDEV_READ_STATUS_SYNC;
  }
  // libevdev drops what a resync left unread when normal reading resumes.
  f.syncing = false;
  f.pending_sync.clear();
  if (f.next >= f.script.size()) return -EAGAIN;
  const auto& step = f.script[f.next++];
  if (step.kind == palpa::testing::EvdevStep::kGone) {
    --f.next;  // gone stays gone
    return -ENODEV;
  }
  if (step.kind == palpa::testing::EvdevStep::kDropped) {
    input_event last = step.event;
    for (const input_event& e : step.lost) {
      Apply(f.device_state, e);
      last = e;
    }
    // The differences between the device's state and what the reader last saw, then a report.
    for (const auto& [key, value] : f.device_state) {
      const auto seen = f.reader_state.find(key);
      if (seen == f.reader_state.end() || seen->second != value)
        f.pending_sync.push_back(palpa::testing::Ev(0, key.first, key.second, value));
    }
    for (input_event& e : f.pending_sync) e.time = last.time;
    input_event report = last;
    report.type = EV_SYN;
    report.code = SYN_REPORT;
    report.value = 0;
    f.pending_sync.push_back(report);
    f.syncing = true;
    *ev = step.event;
    ev->type = EV_SYN;
    ev->code = SYN_DROPPED;
    return LIBEVDEV_READ_STATUS_SYNC;
  }
  *ev = step.event;
  Apply(f.device_state, *ev);
  Apply(f.reader_state, *ev);
  return LIBEVDEV_READ_STATUS_SUCCESS;
}

}  // extern "C"
