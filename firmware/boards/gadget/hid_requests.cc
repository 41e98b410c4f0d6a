// The HID interface's control requests: its class requests (idle, protocol, report) and its HID and
// report descriptors, as a host asks for them on ep0.
#include "hid_requests.h"

#include "usb_descriptors.h"

namespace palpa::gadget {

// Class requests and descriptors; everything else stalls.
bool HidSetup(const usb_ctrlrequest& r, std::vector<uint8_t>* reply) {
  constexpr uint8_t kGetReport = 0x01, kGetIdle = 0x02, kGetProtocol = 0x03, kSetIdle = 0x0A,
                    kSetProtocol = 0x0B;
  const uint8_t type = r.bRequestType & USB_TYPE_MASK;
  if (type == USB_TYPE_STANDARD && r.bRequest == USB_REQ_GET_DESCRIPTOR) {
    const uint8_t descriptor = static_cast<uint8_t>(r.wValue >> 8);
    if (descriptor == kHidReportDescriptorType) {
      *reply = HidReportDescriptor();
      return true;
    }
    if (descriptor == kHidClassDescriptor) {
      *reply = HidClassDescriptor();
      return true;
    }
    return false;
  }
  if (type != USB_TYPE_CLASS) return false;
  switch (r.bRequest) {
    case kSetIdle:
    case kSetProtocol:
      return true;
    case kGetIdle:
      *reply = {0};
      return true;
    case kGetProtocol:
      *reply = {1};  // report protocol
      return true;
    case kGetReport:
      reply->assign(kHidReportBytes, 0);  // zeros read as empty frames
      return true;
    default:
      return false;
  }
}

}  // namespace palpa::gadget
