// libFuzzer target: the frame decoder and every message decoder, with a round-trip oracle.
// Input byte 0 picks the mode: even = a raw byte stream into the frame decoder; odd = a packet
// (header + body) wrapped in a valid frame, so the fuzzer reaches the codecs past the CRC.
#include <cstdlib>
#include <cstring>

#include "palpa/protocol/codec.h"

namespace pp = palpa::protocol;

namespace {

// decode(x) = m must imply encode(m) = x: the encoding is canonical, so any difference is a bug.
void CheckRoundTrip(const pp::Frame& frame) {
  pp::DispatchFrame(frame, [&](const auto& m, const pp::Header& h) {
    uint8_t packet[pp::kMaxPacketSize];
    const auto n = pp::EncodePacket(m, h.seq, h.flags, packet, sizeof(packet));
    if (!n.ok() || n.value != frame.body_size + pp::kHeaderSize ||
        std::memcmp(packet + pp::kHeaderSize, frame.body, frame.body_size) != 0) {
      std::abort();
    }
    uint8_t wire[pp::kMaxFrameSize];
    const auto w = pp::EncodeFrame(packet, n.value, wire, sizeof(wire));
    if (!w.ok()) std::abort();
    pp::OwningFrameDecoder again;
    int frames = 0;
    for (size_t i = 0; i < w.value; ++i) {
      if (again.Process(wire[i]) == pp::FrameDecoder::Event::kFrame) ++frames;
    }
    if (frames != 1) std::abort();
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const bool packet_mode = (data[0] & 1) != 0;
  ++data;
  --size;
  pp::OwningFrameDecoder decoder;
  if (!packet_mode) {
    for (size_t i = 0; i < size; ++i) {
      if (decoder.Process(data[i]) == pp::FrameDecoder::Event::kFrame)
        CheckRoundTrip(decoder.frame());
    }
    return 0;
  }
  if (size < pp::kHeaderSize || size > pp::kMaxPacketSize) return 0;
  uint8_t wire[pp::kMaxFrameSize];
  const auto w = pp::EncodeFrame(data, size, wire, sizeof(wire));
  if (!w.ok()) std::abort();
  for (size_t i = 0; i < w.value; ++i) {
    if (decoder.Process(wire[i]) == pp::FrameDecoder::Event::kFrame)
      CheckRoundTrip(decoder.frame());
  }
  return 0;
}
