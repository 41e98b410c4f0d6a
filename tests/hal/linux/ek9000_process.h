// The EK9000 emulator (ek9000_emulator.py) as a child process, and a second Modbus client that
// looks at its registers: shared by the module's tests and the Linux board's.
#pragma once

#include <modbus.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <string>
#include <thread>

#include "CppUTest/TestHarness.h"
#include "mini_client.h"
#include "wait_until.h"

namespace palpa::testing {

class Ek9000Emulator {
 public:
  /// `input_volts`: "V,V,..." (nan: a broken wire); `plant`: "" or "plant=TAU_MS:A/G,..." (the
  /// emulator's usage).
  explicit Ek9000Emulator(const char* input_volts, const std::string& plant = "")
      : port_(FreeTcpPort()) {
    const std::string port = std::to_string(port_);
    pid_ = fork();
    if (pid_ == 0) {
      const char* script = PALPA_SOURCE_DIR "/tests/hal/linux/ek9000_emulator.py";
      if (plant.empty()) {
        execl("/usr/bin/python3", "python3", script, port.c_str(), input_volts, nullptr);
      } else {
        execl("/usr/bin/python3", "python3", script, port.c_str(), input_volts, plant.c_str(),
              nullptr);
      }
      _exit(127);
    }
    probe_ = modbus_new_tcp("127.0.0.1", port_);
    modbus_set_response_timeout(probe_, 1, 0);
    up_ = WaitUntil([&] { return modbus_connect(probe_) == 0; }, 10);
  }
  ~Ek9000Emulator() {
    modbus_close(probe_);
    modbus_free(probe_);
    Stop();
  }
  void Stop() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  void Pause() { kill(pid_, SIGSTOP); }
  void Resume() { kill(pid_, SIGCONT); }
  bool up() const { return up_; }
  int port() const { return port_; }
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
  int port_;
  pid_t pid_ = -1;
  modbus_t* probe_ = nullptr;
  bool up_ = false;
};

}  // namespace palpa::testing
