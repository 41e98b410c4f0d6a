// The EK9000 emulator (ek9000_emulator.py) as a child process on the port it picked and announced,
// and a second Modbus client that looks at its registers: shared by the module's tests and the
// Linux board's.
#pragma once

#include <modbus.h>
#include <signal.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "sim_process.h"

namespace palpa::testing {

class Ek9000Emulator {
 public:
  /// `input_volts`: "V,V,..." (nan: a broken wire); `plant`: "" or "plant=TAU_MS:A/G,..." (the
  /// emulator's usage). The emulator picks a free port and announces it; up() once it did.
  explicit Ek9000Emulator(const char* input_volts, const std::string& plant = "") {
    std::vector<std::string> args = {PALPA_SOURCE_DIR "/tests/hal/linux/ek9000_emulator.py", "0",
                                     input_volts};
    if (!plant.empty()) args.push_back(plant);
    // Python and pymodbus take a few hundred ms to start, more on a loaded machine.
    up_ = process_.Start(args, "/usr/bin/python3", 10000);
    const std::string& at = process_.address();  // tcp:127.0.0.1:PORT
    if (up_) port_ = std::atoi(at.c_str() + at.rfind(':') + 1);
    probe_ = modbus_new_tcp("127.0.0.1", port_);
    modbus_set_response_timeout(probe_, 1, 0);
    up_ = up_ && modbus_connect(probe_) == 0;
  }
  ~Ek9000Emulator() {
    modbus_close(probe_);
    modbus_free(probe_);
    Stop();
  }
  void Stop() {
    if (process_.pid() <= 0) return;
    kill(process_.pid(), SIGKILL);
    process_.WaitExit(5000);
  }
  void Pause() { kill(process_.pid(), SIGSTOP); }
  void Resume() { kill(process_.pid(), SIGCONT); }
  bool up() const { return up_; }
  int port() const { return port_; }
  /// What the emulator printed before it was up (why it was not, when not).
  const std::string& output() const { return process_.output(); }
  uint16_t Holding(int address) {
    uint16_t v = 0xDEAD;
    if (modbus_read_registers(probe_, address, 1, &v) != 1) {
      modbus_close(probe_);  // after a pause the next read reconnects
      modbus_connect(probe_);
      if (modbus_read_registers(probe_, address, 1, &v) != 1) FAIL("the emulator did not answer");
    }
    return v;
  }
  void SetHolding(int address, uint16_t value) { modbus_write_register(probe_, address, value); }

 private:
  SimProcess process_;
  int port_ = 0;
  modbus_t* probe_ = nullptr;
  bool up_ = false;
};

}  // namespace palpa::testing
