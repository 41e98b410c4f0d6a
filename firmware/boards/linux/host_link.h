// palpa-linux-board's link to the host: the hosted boards' FdLink (TCP, a pty, a serial device) or
// the board as a USB gadget (palpa_gadget_link: vendor bulk, HID and CDC-ACM, as palpa-gadget).
#pragma once

#include <memory>
#include <string>

#include "fd_link.h"
#include "gadget_link.h"
#include "palpa/hal/byte_link.h"
#include "palpa/hal/linux/opened.h"

namespace palpa::linux_board {

class HostLink {
 public:
  /// `spec` as the board file's link.listen: tcp:, pty:, tty: or usb / usb:UDC. kUnavailable
  /// when it cannot be opened, the message naming link.listen.
  hal::Done Open(const std::string& spec, int baud);
  /// Services the link; never blocks.
  void Pump();
  hal::ByteLink& link();
  /// Where a host connects: tcp:HOST:PORT, serial:PATH, or usb:VENDOR:PRODUCT.
  const std::string& address() const { return address_; }
  /// The USB device controller the gadget is bound to; empty for the other links.
  std::string udc() const { return usb_ ? usb_->udc() : std::string(); }
  /// Whether the USB link found its gadget left by a program that died, and removed it.
  bool stale_gadget_removed() const { return usb_ && usb_->stale_removed(); }

 private:
  std::unique_ptr<hosted::FdLink> fd_;
  std::unique_ptr<gadget::GadgetLink> usb_;
  std::string address_;
};

}  // namespace palpa::linux_board
