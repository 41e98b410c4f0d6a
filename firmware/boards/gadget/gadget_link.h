// The board's host link over USB device mode: one composite gadget with a vendor bulk interface
// (FunctionFS), a HID interface with 64-byte reports every 1 ms (FunctionFS) and a CDC-ACM
// serial port (the kernel's function), carried as one byte stream. Bytes from the host on any
// interface go to the board; the board's bytes go to the interface the host last spoke on.
#pragma once

#include <poll.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "configfs_gadget.h"
#include "gadget_channel.h"
#include "palpa/hal/byte_link.h"

namespace palpa::gadget {

struct GadgetLinkOptions {
  std::string name =
      "palpa";      ///< the configfs gadget and the FunctionFS instances are named after it
  std::string udc;  ///< empty: the first USB device controller
  std::string mount_root = "/run/palpa-gadget";  ///< where the FunctionFS instances are mounted
  GadgetIdentity identity;
  bool bulk = true, hid = true, acm = true;
};

struct GadgetCounters {
  uint64_t bytes_from_host[4] = {};  ///< by Channel
  uint64_t bytes_to_host[4] = {};
  uint64_t hid_reports = 0;  ///< input reports sent
  uint64_t dropped = 0;      ///< board bytes with no interface to go to (or left for another)
};

class GadgetLink final : public hal::ByteLink {
 public:
  GadgetLink();
  ~GadgetLink();
  GadgetLink(const GadgetLink&) = delete;
  GadgetLink& operator=(const GadgetLink&) = delete;

  /// Claims the gadget's name (refused while a running program holds it), takes down a gadget of
  /// that name a dead program left, makes the gadget, writes the FunctionFS descriptors and binds
  /// it to the controller.
  bool Open(const GadgetLinkOptions& options, std::string* error);
  /// Unbinds (the host sees the device unplugged) and removes the gadget.
  void Close();

  /// Services the interfaces: host events, finished transfers, the serial port; queues what the
  /// board wrote. Never blocks.
  void Pump();
  /// What to wait on (with poll) before the next Pump, and for how long at most (ms, -1: no limit).
  std::vector<pollfd> PollFds() const;
  int PollTimeoutMs() const;

  Channel active() const { return active_; }
  const GadgetCounters& counters() const { return counters_; }
  const std::string& configfs_path() const;
  const std::string& udc() const;
  const std::string& acm_device() const { return acm_device_; }
  /// Whether Open found a gadget of its name left by a program that died, and removed it.
  bool stale_removed() const { return stale_removed_; }

 private:
  size_t DoRead(uint8_t* out, size_t capacity) override;
  size_t DoWrite(const uint8_t* data, size_t size) override;
  size_t DoWriteSpace() const override;

  struct Impl;
  void FromHost(Channel channel, const uint8_t* data, size_t size);
  void Deactivate(Channel channel);
  void Transmit();
  bool OpenAcm();

  static constexpr size_t kTxCapacity = 4096;  ///< about an MCU's USB transmit buffer
  std::unique_ptr<Impl> impl_;
  Channel active_ = Channel::kNone;
  std::vector<uint8_t> rx_, tx_;
  size_t rx_read_ = 0;
  std::string acm_device_;
  bool stale_removed_ = false;
  GadgetCounters counters_;
};

}  // namespace palpa::gadget
