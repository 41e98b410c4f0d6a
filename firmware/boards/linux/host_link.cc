// Opens the link the board file names and services it.
#include "host_link.h"

#include <cstdio>

namespace palpa::linux_board {

hal::Done HostLink::Open(const std::string& spec, int baud) {
  std::string why;  // the gadget's and the hosted boards' links say it in words
  if (spec == "usb" || spec.rfind("usb:", 0) == 0) {
    gadget::GadgetLinkOptions options;
    if (spec.size() > 4) options.udc = spec.substr(4);
    usb_ = std::make_unique<gadget::GadgetLink>();
    if (!usb_->Open(options, &why)) {
      usb_.reset();
      return {hal::Status::kUnavailable, "link.listen: " + spec + ": " + why};
    }
    char id[16];
    std::snprintf(id, sizeof(id), "%04x:%04x", options.identity.vendor, options.identity.product);
    address_ = std::string("usb:") + id;
    return {};
  }
  fd_ = std::make_unique<hosted::FdLink>();
  if (!fd_->Open(spec, &why, "link.listen", baud)) {
    fd_.reset();
    return {hal::Status::kUnavailable, why};
  }
  address_ = fd_->address();
  return {};
}

void HostLink::Pump() {
  if (usb_) usb_->Pump();
  if (fd_) fd_->Pump();
}

hal::ByteLink& HostLink::link() {
  if (usb_) return *usb_;
  return *fd_;
}

}  // namespace palpa::linux_board
