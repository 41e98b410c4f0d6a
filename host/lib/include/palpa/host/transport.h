// One interface for every way to reach a board: serial, TCP, USB HID, USB bulk, a simulator child.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "palpa/host/outcome.h"

namespace palpa::host {

class Transport {
 public:
  virtual ~Transport() = default;
  /// Reads what has arrived, waiting at most timeout_ms for the first byte. Returns the count
  /// (0 on timeout), or kDisconnected / kIoError.
  virtual protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) = 0;
  /// Writes every byte or fails (kDisconnected, kIoError, kTimeout).
  virtual Status Write(const uint8_t* data, size_t size) = 0;
  /// What this transport is connected to, for messages ("tcp:127.0.0.1:5555").
  virtual std::string Describe() const = 0;
};

/// Opens a transport from a device URI:
///   sim[:CONFIG]              starts palpa-sim (thesis-5finger by default) and connects
///   serial:PATH[?baud=N]      termios raw mode: USB CDC-ACM, UART adapters, ptys
///   tcp:HOST:PORT
///   hid:VID:PID[:SERIAL]      hidapi, 64-byte reports (hex ids)
///   usb:VID:PID[:SERIAL]      libusb vendor interface, one bulk IN and one bulk OUT endpoint
/// On failure the status and a message naming the part at fault. For a sim: URI with
/// `sim_truth_address` non-null the simulator also streams its truth side channel, and
/// *sim_truth_address receives where ("tcp:127.0.0.1:PORT"); other URIs leave it as it was.
Result<std::unique_ptr<Transport>> OpenTransport(const std::string& uri,
                                                 std::string* sim_truth_address = nullptr);

/// Starts palpa-sim with CONFIG and extra options (e.g. {"--plant", "3", "--speed", "4"}) and
/// connects to it. With `truth_address` non-null the simulator also streams its truth side channel
/// (for demos and benchmarks) and *truth_address receives where ("tcp:127.0.0.1:PORT"); with
/// `rig_address` non-null (and --rig-modbus among the options) it waits for the rig's address too.
/// `announcement`, when given, receives the line in which palpa-sim says what it runs
/// ("palpa-sim: thesis-5finger, plant level 3, unit 12, seed 1, speed 1x").
Result<std::unique_ptr<Transport>> LaunchSim(const std::string& config,
                                             const std::vector<std::string>& options,
                                             std::string* truth_address,
                                             std::string* rig_address = nullptr,
                                             std::string* announcement = nullptr);

/// Where palpa-sim is: $PALPA_SIM, next to the running executable, installed beside the library
/// (an application or python3 using an installed libpalpa), the build tree, or PATH.
std::string FindPalpaSim();

/// The pid.codes test id palpa uses until one is allocated.
inline constexpr uint16_t kUsbVendorId = 0x1209;
inline constexpr uint16_t kUsbProductId = 0x0001;

}  // namespace palpa::host
