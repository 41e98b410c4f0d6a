// palpa-linux-board's configuration: one JSON file naming the core's board configuration, the
// analogue I/O module, the GPIO lines, the host link, the watchdog device and real-time settings.
#pragma once

#include <string>
#include <vector>

#include "palpa/core/board_config.h"
#include "palpa/hal/linux/modbus_aio_config.h"
#include "palpa/hal/linux/opened.h"

namespace palpa::linux_board {

struct BoardFile {
  std::string board = "thesis-5finger";  ///< the compiled-in core configuration
  const core::BoardConfig* config = nullptr;
  uint32_t board_id = 1;
  /// tcp:HOST:PORT, pty:PATH, tty:DEVICE, or usb / usb:UDC (the board as a USB gadget on the
  /// first or the named device controller: vendor bulk, HID and CDC-ACM, as palpa-gadget)
  std::string listen = "tcp:127.0.0.1:5600";
  int baud = 115200;  ///< tty only
  hal::linux_aio::ModbusAioConfig module;
  // GPIO lines as CHIP:LINE; empty: not fitted (the host tests run without GPIO).
  std::string supply_enable, dump_enable, pump_enable;
  std::vector<std::string> valves;  ///< line i's dump valve driver (powered: closed)
  std::string estop;
  bool estop_active_high = true;
  std::string watchdog;        ///< a watchdog device (/dev/watchdog); empty: none
  int watchdog_timeout_s = 0;  ///< 0: the driver's own
  int rt_priority = 50;        ///< SCHED_FIFO priority; 0: not asked for
};

/// Parses the file's text; every refusal (kBadValue) names its field ("gpio.valves[2]: ...").
/// Checks the board configuration against the module too (FitsTheModule).
hal::Opened<BoardFile> ParseBoardFile(const std::string& json_text);
/// Reads and parses a file; a refusal's message starts with its path (kIoError: unreadable).
hal::Opened<BoardFile> LoadBoardFile(const std::string& path);

/// Whether `config`'s lines can sit on `module`: no more lines than outputs, sensors within the
/// inputs, the same resolutions, a 0-10 V signal, and a safe value commanded by 0 V on every line
/// (the module's only fallback when the controller dies). Refused (kBadValue) naming the line.
hal::Done FitsTheModule(const core::BoardConfig& config, const std::string& name,
                        const hal::linux_aio::ModbusAioConfig& module);

/// The rule of the module's fallback, in one place: FitsTheModule applies it to the file's board
/// at start, and it is the board's line check (core::BoardIo::line_check), so a host's
/// configuration change is held to it too. Why the line is refused, or nullptr when 0 V commands
/// its safe value.
const char* SafeValueNotAtZeroVolts(const protocol::ConfigureLine& line);
/// The DAC code the line's safe value commands (0: 0 V).
uint32_t SafeValueCode(const protocol::ConfigureLine& line);

}  // namespace palpa::linux_board
