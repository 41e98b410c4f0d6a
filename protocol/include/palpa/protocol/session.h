// Session rules of both sides: who may send what before Hello, boot-nonce tracking, catalog check.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/catalog.h"
#include "palpa/protocol/messages_bootstrap.h"
#include "palpa/protocol/status.h"

namespace palpa::protocol {

/// Board side: before Hello (or after a reset) everything but Hello and EStop is refused.
constexpr Status BoardAdmit(bool session_open, uint8_t type) {
  if (type == static_cast<uint8_t>(MessageType::kHello) ||
      type == static_cast<uint8_t>(MessageType::kEStop)) {
    return Status::kOk;
  }
  return session_open ? Status::kOk : Status::kNoSession;
}

/// Host side of a session: matches HelloReply to our Hello, notices board resets from the boot
/// nonce in every board frame, and refuses non-bootstrap traffic across a catalog mismatch.
class HostSession {
 public:
  explicit HostSession(uint32_t local_catalog_hash = kCatalogHash)
      : local_catalog_(local_catalog_hash) {}

  /// Remembers the Hello we are about to send.
  void BeginHello(uint32_t host_nonce) {
    host_nonce_ = host_nonce;
    hello_pending_ = true;
  }

  /// Returns kOk (session open), kCatalogMismatch (open for the bootstrap set only) or
  /// kStale (a reply to some other Hello; ignore it).
  Status OnHelloReply(const HelloReply& reply);

  enum class BootCheck : uint8_t { kSame, kReset, kNoSession };
  /// Compares the boot nonce of a board frame with the session's. kReset: the board rebooted;
  /// in-flight commands have an unknown outcome and a new Hello is needed.
  BootCheck CheckBootNonce(uint32_t boot_nonce) const {
    if (!open_) return BootCheck::kNoSession;
    return boot_nonce == board_.boot_nonce ? BootCheck::kSame : BootCheck::kReset;
  }

  /// May the host send a message of this type now?
  Status Admit(uint8_t type) const;

  /// Writes "host catalog 0x…  (protocol 1) vs board catalog 0x… (firmware a.b.c, protocol 1)"
  /// into out (NUL-terminated, truncated to capacity). Returns the length written.
  size_t DescribeVersions(char* out, size_t capacity) const;

  void Close() { open_ = false; }
  bool open() const { return open_; }
  bool catalog_matches() const { return open_ && board_.catalog_hash == local_catalog_; }
  const HelloReply& board() const { return board_; }
  uint32_t local_catalog() const { return local_catalog_; }

 private:
  uint32_t local_catalog_;
  uint32_t host_nonce_ = 0;
  bool hello_pending_ = false;
  bool open_ = false;
  HelloReply board_{};
};

}  // namespace palpa::protocol
