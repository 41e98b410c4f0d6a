// The gadget's interfaces a host can speak on, and their names in the board's messages.
#pragma once

#include <cstdint>

namespace palpa::gadget {

enum class Channel : uint8_t { kNone, kBulk, kHid, kAcm };

inline const char* ChannelName(Channel channel) {
  switch (channel) {
    case Channel::kBulk:
      return "bulk";
    case Channel::kHid:
      return "hid";
    case Channel::kAcm:
      return "acm";
    default:
      return "none";
  }
}

}  // namespace palpa::gadget
