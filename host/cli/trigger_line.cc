// The study's trigger line: a GPIO output pulsed at each trigger event.
#include "trigger_line.h"

#include <chrono>
#include <cstdio>
#include <thread>

namespace palpa::cli {

host::Result<std::shared_ptr<TriggerLine>> TriggerLine::Open(const std::string& spec) {
  auto line = hal::linux_gpio::GpioOutput::Open(spec, false);
  // Every failure an I/O error, as the option has always reported it (its exit status).
  if (!line.ok()) return {host::Status::kIoError, "--trigger-gpio " + line.message};
  return std::shared_ptr<TriggerLine>(new TriggerLine(std::move(line.value)));
}

void TriggerLine::Pulse(const char* who) {
  const bool up = line_->Set(true) == hal::Status::kOk;
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const bool down = line_->Set(false) == hal::Status::kOk;
  if (!(up && down) && !said_) {  // said once: a session's every event would repeat it
    std::fprintf(stderr, "%s: the trigger line's write failed\n", who);
    said_ = true;
  }
}

}  // namespace palpa::cli
