// Host-side session state and the version text used when catalogs differ.
#include "palpa/protocol/session.h"

namespace palpa::protocol {
namespace {

// Minimal bounded text writer (no printf on the freestanding side).
class TextOut {
 public:
  TextOut(char* out, size_t capacity) : out_(out), capacity_(capacity) {
    if (capacity_ > 0) out_[0] = '\0';
  }
  TextOut& Str(const char* s) {
    while (*s != '\0') Put(*s++);
    return *this;
  }
  TextOut& Dec(uint32_t v) {
    char digits[10];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v != 0);
    while (n > 0) Put(digits[--n]);
    return *this;
  }
  TextOut& Hex32(uint32_t v) {
    Str("0x");
    for (int shift = 28; shift >= 0; shift -= 4) Put("0123456789abcdef"[(v >> shift) & 0xFu]);
    return *this;
  }
  size_t length() const { return length_; }

 private:
  void Put(char c) {
    if (length_ + 1 >= capacity_) return;
    out_[length_++] = c;
    out_[length_] = '\0';
  }
  char* out_;
  size_t capacity_;
  size_t length_ = 0;
};

}  // namespace

Status HostSession::OnHelloReply(const HelloReply& reply) {
  if (!hello_pending_ || reply.host_nonce != host_nonce_) return Status::kStale;
  hello_pending_ = false;
  board_ = reply;
  open_ = true;
  return catalog_matches() ? Status::kOk : Status::kCatalogMismatch;
}

Status HostSession::Admit(uint8_t type) const {
  if (type == static_cast<uint8_t>(MessageType::kHello) ||
      type == static_cast<uint8_t>(MessageType::kEStop)) {
    return Status::kOk;
  }
  if (!open_) return Status::kNoSession;
  if (!IsBootstrap(type) && !catalog_matches()) return Status::kCatalogMismatch;
  return Status::kOk;
}

size_t HostSession::DescribeVersions(char* out, size_t capacity) const {
  TextOut text(out, capacity);
  text.Str("host catalog ").Hex32(local_catalog_).Str(" (protocol ").Dec(kProtocolVersion);
  text.Str(") vs board catalog ").Hex32(board_.catalog_hash).Str(" (firmware ");
  text.Dec(board_.firmware_major).Str(".").Dec(board_.firmware_minor).Str(".");
  text.Dec(board_.firmware_patch).Str(", protocol ").Dec(board_.protocol_version).Str(")");
  return text.length();
}

}  // namespace palpa::protocol
