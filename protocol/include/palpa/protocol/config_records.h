// Configuration records: a configuration as a run of Configure* messages, each
// [u16 body length, little-endian][u8 message type][body as the codec encodes it]. The bytes of a
// staged upload (StagedPart) and of the board's stored configuration; host and board both write
// and read them through this one definition.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/codec.h"
#include "palpa/protocol/little_endian.h"

namespace palpa::protocol {

inline constexpr size_t kRecordHeaderSize = 3;

/// Writes `message` as one record at `out`; returns the record's size (header included), or
/// kOverflow when it does not fit in `capacity`.
template <class M>
Result<size_t> EncodeRecord(const M& message, uint8_t* out, size_t capacity) {
  if (capacity < kRecordHeaderSize) return Status::kOverflow;
  const Result<size_t> body =
      EncodeBody(message, out + kRecordHeaderSize, capacity - kRecordHeaderSize);
  if (!body.ok()) return Status::kOverflow;
  StoreLe16(out, static_cast<uint16_t>(body.value));
  out[2] = static_cast<uint8_t>(M::kInfo.type);
  return kRecordHeaderSize + body.value;
}

/// One record of a blob: its message type and body (pointing into the blob).
struct Record {
  uint8_t type = 0;
  const uint8_t* body = nullptr;
  size_t size = 0;
};

/// Walks the records of a blob in order. Next() refuses a record whose header or body the blob
/// cuts short (kBadLength, with a reason for people); the walk ends there.
class RecordReader {
 public:
  RecordReader(const uint8_t* blob, size_t size) : blob_(blob), size_(size) {}

  bool done() const { return at_ >= size_; }
  /// Records read so far.
  uint8_t index() const { return index_; }

  Status Next(Record& record, const char** reason = nullptr) {
    const char* why = nullptr;
    if (size_ - at_ < kRecordHeaderSize) {
      why = "truncated record header";
    } else if (size_ - at_ - kRecordHeaderSize < LoadLe16(blob_ + at_)) {
      why = "record longer than the blob";
    }
    if (why != nullptr) {
      if (reason != nullptr) *reason = why;
      at_ = size_;
      return Status::kBadLength;
    }
    record = Record{blob_[at_ + 2], blob_ + at_ + kRecordHeaderSize, LoadLe16(blob_ + at_)};
    at_ += kRecordHeaderSize + record.size;
    ++index_;
    return Status::kOk;
  }

 private:
  const uint8_t* blob_;
  size_t size_;
  size_t at_ = 0;
  uint8_t index_ = 0;
};

}  // namespace palpa::protocol
