// Encoding and decoding of whole messages and packets, and dispatch of a frame to a handler.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/catalog.h"
#include "palpa/protocol/field_codec.h"
#include "palpa/protocol/framing.h"
#include "palpa/protocol/wire.h"

namespace palpa::protocol {

template <class M>
concept HasCheck = requires(const M& m) {
  M::Check(m);
};

/// Encodes the body of `m` into out[0..capacity). Returns the body size, or the failing status
/// (kOutOfRange, kBadValue, kOverflow) with the field in *error.
template <class M>
Result<size_t> EncodeBody(const M& m, uint8_t* out, size_t capacity, FieldError* error = nullptr) {
  BodyEncoder encoder(out, capacity);
  M::Fields(encoder, m);
  FieldError failure = encoder.error();
  if constexpr (HasCheck<M>) {
    if (failure.status == Status::kOk) {
      if (const char* field = M::Check(m)) failure = FieldError{Status::kBadValue, field, 0};
    }
  }
  if (error != nullptr) *error = failure;
  if (failure.status != Status::kOk) return failure.status;
  return encoder.size();
}

/// Decodes a whole body: every byte must be consumed and every rule hold.
template <class M>
Status DecodeBody(const uint8_t* body, size_t size, M& m, FieldError* error = nullptr) {
  BodyDecoder decoder(body, size);
  M::Fields(decoder, m);
  decoder.Finish();
  if constexpr (HasCheck<M>) {
    if (decoder.ok()) {
      if (const char* field = M::Check(m)) decoder.Reject(Status::kBadValue, field);
    }
  }
  if (error != nullptr) *error = decoder.error();
  return decoder.error().status;
}

/// Writes header + body of `m` into out (at most kMaxPacketSize bytes are used).
template <class M>
Result<size_t> EncodePacket(const M& m, uint8_t seq, uint8_t header_flags, uint8_t* out,
                            size_t capacity, FieldError* error = nullptr) {
  if (capacity < kHeaderSize) return Status::kOverflow;
  const size_t limit = capacity < kMaxPacketSize ? capacity : kMaxPacketSize;
  WriteHeader(Header{kProtocolVersion, static_cast<uint8_t>(M::kInfo.type), seq, header_flags},
              out);
  const Result<size_t> body = EncodeBody(m, out + kHeaderSize, limit - kHeaderSize, error);
  if (!body.ok()) return body.status;
  return kHeaderSize + body.value;
}

/// Encodes `m` all the way to a delimited frame in out (kMaxFrameSize bytes always suffice).
template <class M>
Result<size_t> EncodeMessageFrame(const M& m, uint8_t seq, uint8_t header_flags, uint8_t* out,
                                  size_t capacity, FieldError* error = nullptr) {
  uint8_t packet[kMaxPacketSize + kCrcSize];
  const Result<size_t> size = EncodePacket(m, seq, header_flags, packet, kMaxPacketSize, error);
  if (!size.ok()) return size.status;
  return EncodeFrameInPlace(packet, size.value, out, capacity);
}

/// Decodes a frame's body as the message its header names and calls handler(message, header).
/// Returns kUnsupported for a type not in `List` (handler not called) or the decode status. A
/// board that speaks part of the catalog (the bootloader's recovery mode) names its part, and
/// decoders for the rest are not even compiled in.
template <class List, class Handler>
Status DispatchFrameOf(const Frame& frame, Handler&& handler, FieldError* error = nullptr) {
  Status result = Status::kUnsupported;
  ForEachMessage(List{}, [&]<class M>() {
    if (static_cast<uint8_t>(M::kInfo.type) != frame.header.type) return;
    M message{};
    result = DecodeBody(frame.body, frame.body_size, message, error);
    if (result == Status::kOk) handler(message, frame.header);
  });
  if (result == Status::kUnsupported && error != nullptr) {
    *error = FieldError{Status::kUnsupported, "type", 1};
  }
  return result;
}

/// DispatchFrameOf the whole catalog.
template <class Handler>
Status DispatchFrame(const Frame& frame, Handler&& handler, FieldError* error = nullptr) {
  return DispatchFrameOf<Catalog>(frame, handler, error);
}

}  // namespace palpa::protocol
