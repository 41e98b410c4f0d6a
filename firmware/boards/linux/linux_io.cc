// palpa-linux-board's hardware: opened in a safe state, driven by the core, made safe at the end.
#include "linux_io.h"

#include <time.h>

#include <cstdio>
#include <utility>

namespace palpa::linux_board {

uint64_t MonotonicClock::DoNowMicros() {
  timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<uint64_t>(now.tv_sec) * 1000000u + static_cast<uint64_t>(now.tv_nsec) / 1000u;
}

bool EstopInput::DoRead() {
  const bool asserted = line->Read();
  if (!said_ && !line->error().empty()) {
    std::fprintf(
        stderr,
        "palpa-linux-board: gpio.estop %s; the E-stop counts as pressed (estop_pin) from now on\n",
        line->error().c_str());
    said_ = true;
  }
  return asserted;
}

std::unique_ptr<LinuxIo> LinuxIo::Open(const BoardFile& file, std::string* error) {
  std::unique_ptr<LinuxIo> io(new LinuxIo());
  // GPIO first, every line low: nothing is powered while the module is reached.
  auto output = [&](const char* field, const std::string& spec,
                    std::unique_ptr<hal::linux_gpio::GpioOutput>* out) {
    if (spec.empty()) return true;
    auto opened = hal::linux_gpio::GpioOutput::Open(spec, false);
    if (!opened.ok()) {
      *error = std::string("gpio.") + field + ": " + opened.message;
      return false;
    }
    *out = std::move(opened.value);
    return true;
  };
  if (!output("supply_enable", file.supply_enable, &io->supply_.line) ||
      !output("dump_enable", file.dump_enable, &io->dump_.line) ||
      !output("pump_enable", file.pump_enable, &io->pump_.line)) {
    return nullptr;
  }
  for (size_t i = 0; i < file.valves.size(); ++i) {
    io->valves_.valves.emplace_back();
    const std::string field = "valves[" + std::to_string(i) + "]";
    if (!output(field.c_str(), file.valves[i], &io->valves_.valves.back())) return nullptr;
  }
  if (!file.estop.empty()) {
    // The file names the level that asserts the E-stop; the line is requested in that sense.
    auto estop = hal::linux_gpio::GpioEdgeInput::Open(file.estop,
                                                      /*active_low=*/!file.estop_active_high);
    if (!estop.ok()) {
      *error = "gpio.estop: " + estop.message;
      return nullptr;
    }
    io->estop_.line = std::move(estop.value);
  }
  auto module = hal::linux_aio::ModbusAioModule::Open(file.module);
  if (!module.ok()) {
    *error = "analog_module: " + module.message;
    return nullptr;
  }
  io->module_ = std::move(module.value);
  return io;
}

core::BoardIo LinuxIo::Io(hal::ByteLink& link) {
  core::BoardIo io{clock_,
                   module_->outputs(),
                   &module_->inputs(),
                   supply_,
                   dump_,
                   pump_,
                   estop_.line ? &estop_ : nullptr,
                   link,
                   nullptr,
                   0};
  if (!valves_.valves.empty()) io.line_vents = &valves_;
  io.line_check = SafeValueNotAtZeroVolts;
  return io;
}

bool LinuxIo::WriteSafe(std::string* error) {
  // The module first: the regulators vent on 0 V whatever the valves do.
  const bool module_ok = module_->WriteSafe() == protocol::Status::kOk;
  if (!module_ok) *error = module_->last_error();
  // Each line once, every one tried: a line that refuses is named, not retried.
  std::string refused;
  auto low = [&refused](hal::DigitalOutput& output, const char* name) {
    if (output.Set(false) == protocol::Status::kOk) return;
    refused += (refused.empty() ? "" : ", ") + std::string(name);
  };
  low(supply_, "gpio.supply_enable");
  low(dump_, "gpio.dump_enable");
  low(pump_, "gpio.pump_enable");
  const uint8_t valve = valves_.Write(~0u);  // every valve driver released
  if (valve != hal::DigitalPort::kAllWritten) {
    refused +=
        (refused.empty() ? "" : ", ") + std::string("gpio.valves[") + std::to_string(valve) + "]";
  }
  if (!refused.empty()) {
    const std::string gpio = "GPIO lines not set low: " + refused;
    *error = module_ok ? gpio : *error + "; " + gpio;
  }
  return module_ok && refused.empty();
}

size_t LinuxIo::gpio_lines() const {
  size_t n = valves_.valves.size() + (estop_.line ? 1 : 0);
  for (const OptionalOutput* o : {&supply_, &dump_, &pump_}) n += o->line ? 1 : 0;
  return n;
}

}  // namespace palpa::linux_board
