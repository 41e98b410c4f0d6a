// SCHED_FIFO and mlockall, and the absolute-deadline sleep.
#include "realtime.h"

#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace palpa::linux_board {

RealTimeReport EnterRealTime(int priority) {
  RealTimeReport r;
  // Under a finite RLIMIT_MEMLOCK, MCL_FUTURE would make every allocation past the limit fail
  // later, in the middle of running: without the privilege to exceed it, memory stays unlocked.
  rlimit limit{};
  getrlimit(RLIMIT_MEMLOCK, &limit);
  if (geteuid() != 0 && limit.rlim_cur != RLIM_INFINITY) {
    r.locked_why = "RLIMIT_MEMLOCK is " + std::to_string(limit.rlim_cur / 1024) +
                   " KiB; raise it to unlimited (LimitMEMLOCK=infinity)";
  } else {
    r.locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
    if (!r.locked) r.locked_why = std::strerror(errno);
  }
  if (priority > 0) {
    sched_param param{};
    param.sched_priority = priority;
    r.fifo = sched_setscheduler(0, SCHED_FIFO, &param) == 0;
    if (!r.fifo) r.fifo_why = std::strerror(errno);
  } else {
    r.fifo_why = "realtime.priority is 0";
  }
  return r;
}

std::string RealTimeReport::Describe(int priority) const {
  std::string s = fifo ? "SCHED_FIFO priority " + std::to_string(priority)
                       : "not SCHED_FIFO (" + fifo_why + ")";
  s += locked ? ", memory locked" : ", memory not locked (" + locked_why + ")";
  if (!fifo || !locked) s += "; ticks may be late: see the tick statistics (docs/linux.md)";
  return s;
}

uint64_t MonotonicNs() {
  timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<uint64_t>(now.tv_sec) * 1000000000u + static_cast<uint64_t>(now.tv_nsec);
}

bool DeadlineGrid::Sleep() {
  const timespec at{static_cast<time_t>(next_ns_ / 1000000000u),
                    static_cast<long>(next_ns_ % 1000000000u)};
  return clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) == 0;
}

void DeadlineGrid::Advance(uint64_t now_ns) {
  next_ns_ += period_ns_;
  if (now_ns >= next_ns_) next_ns_ += ((now_ns - next_ns_) / period_ns_ + 1) * period_ns_;
}

}  // namespace palpa::linux_board
