// A minimal host built only on protocol/, for end-to-end tests against palpa-sim.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "palpa/protocol/codec.h"
#include "received_frame.h"

namespace palpa::testing {

namespace pp = palpa::protocol;

/// Bytes to and from a board by some other way than a file descriptor (a host Transport: USB,
/// HID), so this client stays free of the host library.
class BytePipe {
 public:
  virtual ~BytePipe() = default;
  virtual void Write(const uint8_t* data, size_t size) = 0;
  /// Bytes read within timeout_ms (0: none), or -1 when the pipe is gone.
  virtual long Read(uint8_t* out, size_t capacity, int timeout_ms) = 0;
};

class MiniClient {
 public:
  ~MiniClient();
  bool ConnectTcp(const std::string& host, int port);
  bool OpenSerial(const std::string& path);
  void Use(std::unique_ptr<BytePipe> pipe) { pipe_ = std::move(pipe); }
  void Close();

  void SendBytes(const std::vector<uint8_t>& bytes);
  /// A message naming a session with none named (0) names this client's: its last Hello's nonce.
  template <class M>
  void Send(M m, uint8_t seq = 0, uint8_t flags = 0) {
    if constexpr (requires { m.session; }) {
      if (m.session == 0) m.session = session_;
    }
    uint8_t frame[pp::kMaxFrameSize];
    const auto n = pp::EncodeMessageFrame(m, seq, flags, frame, sizeof(frame));
    SendBytes(std::vector<uint8_t>(frame, frame + n.value));
  }
  /// While reading or waiting for answers, sends a Heartbeat whenever nothing was sent for
  /// `every_ms` (0: never), as a host keeps a session alive; silence starts when it is turned off.
  void KeepAlive(int every_ms) { keepalive_ms_ = every_ms; }
  /// Frames received within timeout_ms (returns early once `until` says so).
  std::vector<ReceivedFrame> Read(int timeout_ms, bool (*until)(const ReceivedFrame&) = nullptr);

  /// Raw text received within timeout_ms (for the truth side channel).
  std::string ReadText(int timeout_ms);
  /// Hello and its reply (status kTimeout in .status when none came).
  pp::Result<pp::HelloReply> Hello(uint32_t nonce, int timeout_ms = 2000);
  /// Sends a reliable command with the next seq and waits for its Ack or Nack.
  template <class M>
  pp::Status Reliable(const M& m, int timeout_ms = 2000) {
    const uint8_t seq = next_seq_++;
    Send(m, seq, pp::flags::kReliable);
    return WaitAnswer(seq, static_cast<uint8_t>(M::kInfo.type), timeout_ms);
  }
  /// Puts finger `finger` in raw mode (reliable) and streams one setpoint to `line` (generation
  /// `generation`); returns the mode command's answer.
  pp::Status RawSetpoint(uint8_t finger, uint8_t line, int32_t pa, uint32_t generation = 1);
  /// Everything received while waiting, telemetry included.
  std::vector<ReceivedFrame> backlog;

 private:
  pp::Status WaitAnswer(uint8_t seq, uint8_t type, int timeout_ms);
  int fd_ = -1;
  uint32_t session_ = 0;
  std::unique_ptr<BytePipe> pipe_;
  uint8_t next_seq_ = 0;
  int keepalive_ms_ = 0;
  int64_t last_sent_ms_ = 0;
  uint32_t heartbeat_generation_ = 0;
  pp::OwningFrameDecoder decoder_;
};

}  // namespace palpa::testing
