// One frame a test received from a board: its header and body, decoded on demand.
#pragma once

#include <cstdint>
#include <vector>

#include "palpa/protocol/codec.h"

namespace palpa::testing {

/// One decoded frame from the board.
struct ReceivedFrame {
  protocol::Header header;
  std::vector<uint8_t> body;
  template <class M>
  bool Is() const {
    return header.type == static_cast<uint8_t>(M::kInfo.type);
  }
  template <class M>
  M As() const {
    M m{};
    protocol::DecodeBody(body.data(), body.size(), m);
    return m;
  }
};

}  // namespace palpa::testing
