// Session rules of both sides: who may send what before Hello, boot-nonce tracking, catalog check.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/catalog.h"
#include "palpa/protocol/messages_bootstrap.h"
#include "palpa/protocol/reliable_receiver.h"
#include "palpa/protocol/sequence.h"
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

/// Board side of a session: the boot nonce, the host's Hello, the reliable receiver, the
/// latest-wins gates and when the host was last heard, all reset together by a new Hello. A session
/// belongs to one host: its identity is the nonce of the Hello that opened it, which every stream
/// frame, Close and Release carries. It ends by Close or by silence; until then another host's
/// Hello is refused busy.
class BoardSession {
 public:
  explicit BoardSession(uint32_t boot_nonce) : boot_nonce_(boot_nonce) {}

  enum class HelloVerdict : uint8_t {
    kOpened,  ///< a new session: sequence state and stream generations start afresh
    kRepeat,  ///< the open session's own Hello, retried before its host was heard: answered again
    kBusy,    ///< a session of another host is open: refused with busy, nothing changes
  };

  /// Applies a Hello. The open session's Hello repeated before its host has been heard in the
  /// session (its reply may be lost) changes nothing, so a retried or duplicated Hello can never
  /// rewind the sequence; once heard, the same nonce again is another host reusing it, and busy.
  /// A Hello answered (opened or repeated) at `now_us` starts the host-silence timer again.
  HelloVerdict OnHello(const Hello& hello, uint64_t now_us) {
    if (open_) {
      if (hello.host_nonce != host_nonce_ || heard_) return HelloVerdict::kBusy;
      last_frame_us_ = now_us;
      return HelloVerdict::kRepeat;
    }
    open_ = true;
    last_frame_us_ = now_us;
    heard_ = false;
    host_nonce_ = hello.host_nonce;
    receiver_.Reset(hello.initial_seq);
    setpoints_.Reset();
    targets_.Reset();
    heartbeat_.Reset();
    return HelloVerdict::kOpened;
  }

  Status Admit(uint8_t type) const { return BoardAdmit(open_, type); }

  /// Does a frame naming `session` belong to the open session?
  bool Owns(uint32_t session) const { return open_ && session == host_nonce_; }
  /// A fresh frame of the session arrived at `now_us` (a newer heartbeat, an applied command or
  /// stream frame): its host has the reply, so a Hello with its nonce is no longer a retry, and
  /// the host-silence timer starts again.
  void Heard(uint64_t now_us) {
    heard_ = true;
    last_frame_us_ = now_us;
  }
  /// Close or host silence: the session is over; everything but Hello and EStop is refused.
  void End() {
    open_ = false;
    heard_ = false;
  }

  bool open() const { return open_; }
  bool heard() const { return heard_; }
  /// When the session's host last sent a fresh frame (its Hello included): what the host-silence
  /// timer counts from. Kept after the session ends.
  uint64_t last_frame_us() const { return last_frame_us_; }
  uint32_t boot_nonce() const { return boot_nonce_; }
  uint32_t host_nonce() const { return host_nonce_; }
  ReliableReceiver& receiver() { return receiver_; }
  GenerationGate& setpoints() { return setpoints_; }
  GenerationGate& targets() { return targets_; }
  GenerationGate& heartbeat() { return heartbeat_; }
  const GenerationGate& setpoints() const { return setpoints_; }
  const GenerationGate& targets() const { return targets_; }
  const GenerationGate& heartbeat() const { return heartbeat_; }

 private:
  uint32_t boot_nonce_;
  uint32_t host_nonce_ = 0;
  bool open_ = false;
  bool heard_ = false;
  uint64_t last_frame_us_ = 0;
  ReliableReceiver receiver_;
  GenerationGate setpoints_;
  GenerationGate targets_;
  GenerationGate heartbeat_;
};

/// Host side of a session: matches HelloReply to our Hello, notices board resets from the boot
/// nonce in every board frame, and refuses non-bootstrap traffic across a catalog mismatch.
class HostSession {
 public:
  explicit HostSession(uint32_t local_catalog_hash = kCatalogHash)
      : local_catalog_(local_catalog_hash) {}

  /// Remembers the Hello we are about to send.
  void BeginHello(uint32_t host_nonce) {
    if (host_nonce != host_nonce_) previous_nonce_ = host_nonce_;
    host_nonce_ = host_nonce;
    hello_pending_ = true;
  }

  /// Returns kOk (session open), kCatalogMismatch (open for the bootstrap set only) or
  /// kStale (a reply to some other Hello; ignore it).
  Status OnHelloReply(const HelloReply& reply);

  /// A reply to another host's Hello from the board of this open session: the board has ended
  /// our session (it went silent, or closed) and belongs to that host now.
  bool TakenOverBy(const HelloReply& reply) const {
    return open_ && reply.boot_nonce == board_.boot_nonce && reply.host_nonce != host_nonce_ &&
           reply.host_nonce != previous_nonce_;  // a late reply to our own earlier Hello
  }
  /// What this host's stream frames, Close and Release carry: its Hello's nonce.
  uint32_t session_tag() const { return host_nonce_; }

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
  uint32_t previous_nonce_ = 0;
  bool hello_pending_ = false;
  bool open_ = false;
  HelloReply board_{};
};

}  // namespace palpa::protocol
