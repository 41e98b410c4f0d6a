// What the HID interface answers on ep0: its class requests and its HID and report descriptors.
#pragma once

#include <linux/usb/ch9.h>

#include <cstdint>
#include <vector>

namespace palpa::gadget {

/// A setup request addressed to the HID interface: true with the data for an IN request in
/// `reply` (empty for an OUT one), false to stall it.
bool HidSetup(const usb_ctrlrequest& request, std::vector<uint8_t>* reply);

}  // namespace palpa::gadget
