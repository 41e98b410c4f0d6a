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

/// A TCP port on 127.0.0.1 that was free a moment ago (for servers that cannot pick their own).
int FreeTcpPort();

/// palpa-sim as a child process; stopped with SIGTERM when destroyed. Its output is read for its
/// whole life (a thread after Start), so a child that writes much never blocks on a full pipe.
class SimProcess {
 public:
  SimProcess();
  /// Starts PALPA_SIM_PATH (or `program`: another board, or a server, that announces itself the
  /// same way) with the arguments and waits up to `timeout_ms` for its "listening on" line.
  bool Start(const std::vector<std::string>& args, const char* program = nullptr,
             int timeout_ms = 5000);
  ~SimProcess();
  /// Sends SIGTERM and returns the exit status (-1 if it had to be killed).
  int Stop();
  /// Waits up to `timeout_ms` for it to exit by itself (or by a signal the test sent): its exit
  /// status, -1 when a signal ended it, -2 when it is still running.
  int WaitExit(int timeout_ms);
  const std::string& address() const {
    return address_;
  }  ///< "tcp:127.0.0.1:PORT" or "serial:PATH"
  const std::string& truth_address() const { return truth_address_; }  ///< when --truth was given
  const std::string& rig_address() const { return rig_address_; }  ///< when --rig-modbus was given
  const std::string& netft_address() const {
    return netft_address_;
  }  ///< when --rig-netft was given
  int pid() const { return pid_; }
  /// What it printed (stdout and stderr) until Start returned: its addresses, its warnings, or
  /// why it refused to start.
  const std::string& output() const { return output_; }
  /// What it printed after Start returned, the last 64 KiB of it: for a failure's message.
  std::string later_output() const;

 private:
  struct Drain;
  std::unique_ptr<Drain> drain_;
  int pid_ = -1;
  int out_fd_ = -1;
  std::string address_;
  std::string truth_address_;
  std::string rig_address_;
  std::string netft_address_;
  std::string output_;
};

}  // namespace palpa::testing
