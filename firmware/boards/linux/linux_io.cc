// palpa-linux-board's hardware: opened in a safe state, driven by the core, made safe at the end.
#include "linux_io.h"

#include <time.h>

#include <cstdio>
#include <tuple>
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

hal::Opened<std::unique_ptr<LinuxIo>> LinuxIo::Open(const BoardFile& file) {
  std::unique_ptr<LinuxIo> io(new LinuxIo());
  // GPIO first, every line low: nothing is powered while the module is reached.
  auto output = [](const std::string& field, const std::string& spec,
                   std::unique_ptr<hal::linux_gpio::GpioOutput>& out) -> hal::Done {
    if (spec.empty()) return {};
    auto opened = hal::linux_gpio::GpioOutput::Open(spec, false);
    if (!opened.ok()) return {opened.status, "gpio." + field + ": " + opened.message};
    out = std::move(opened.value);
    return {};
  };
  for (auto [field, spec, line] : {std::tuple("supply_enable", &file.supply_enable, &io->supply_),
                                   std::tuple("dump_enable", &file.dump_enable, &io->dump_),
                                   std::tuple("pump_enable", &file.pump_enable, &io->pump_)}) {
    if (const hal::Done opened = output(field, *spec, line->line); !opened.ok())
      return {opened.status, opened.message};
  }
  for (size_t i = 0; i < file.valves.size(); ++i) {
    io->valves_.valves.emplace_back();
    const std::string field = "valves[" + std::to_string(i) + "]";
    if (const hal::Done opened = output(field, file.valves[i], io->valves_.valves.back());
        !opened.ok())
      return {opened.status, opened.message};
  }
  if (!file.estop.empty()) {
    // The file names the level that asserts the E-stop; the line is requested in that sense.
    auto estop = hal::linux_gpio::GpioEdgeInput::Open(file.estop,
                                                      /*active_low=*/!file.estop_active_high);
    if (!estop.ok()) return {estop.status, "gpio.estop: " + estop.message};
    io->estop_.line = std::move(estop.value);
  }
  auto module = hal::linux_aio::ModbusAioModule::Open(file.module);
  if (!module.ok()) return {module.status, "analog_module: " + module.message};
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

hal::Done LinuxIo::WriteSafe() {
  // The module first: the regulators vent on 0 V whatever the valves do.
  const bool module_ok = module_->WriteSafe() == protocol::Status::kOk;
  std::string why = module_ok ? "" : module_->last_error();
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
  if (module_ok && refused.empty()) return {};
  if (!refused.empty())
    why += (module_ok ? "" : "; ") + std::string("GPIO lines not set low: ") + refused;
  return {hal::Status::kIoError, why};
}

size_t LinuxIo::gpio_lines() const {
  size_t n = valves_.valves.size() + (estop_.line ? 1 : 0);
  for (const OptionalOutput* o : {&supply_, &dump_, &pump_}) n += o->line ? 1 : 0;
  return n;
}

}  // namespace palpa::linux_board
