// A test board and host built only from protocol/ pieces, joined by a seeded lossy channel.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <random>
#include <vector>

#include "palpa/protocol/codec.h"
#include "palpa/protocol/reliable_receiver.h"
#include "palpa/protocol/reliable_sender.h"
#include "palpa/protocol/sequence.h"
#include "palpa/protocol/session.h"

namespace palpa::testing {

namespace pp = palpa::protocol;

/// Frame-level faults of one direction of a link, seeded.
struct ChannelFaults {
  double drop = 0;       ///< probability a frame is lost
  double duplicate = 0;  ///< probability a frame arrives twice
  double corrupt = 0;    ///< probability one random bit of a frame flips
  double byte_loss = 0;  ///< probability per byte of vanishing (delimiters included)
  uint32_t latency_us = 300;
  uint32_t jitter_us = 0;  ///< uniform extra delay: reorders frames when > frame spacing
};

class LossyChannel {
 public:
  LossyChannel(ChannelFaults faults, uint32_t seed) : faults_(faults), rng_(seed) {}
  void Send(const uint8_t* frame, size_t size, uint64_t now_us);
  /// Bytes whose delivery time has come, in delivery order.
  std::vector<uint8_t> Deliver(uint64_t now_us);
  bool idle() const { return queue_.empty(); }

 private:
  bool Chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng_) < p; }
  ChannelFaults faults_;
  std::mt19937 rng_;
  std::multimap<uint64_t, std::vector<uint8_t>> queue_;
};

/// A board that keeps sessions, applies ClearFault(mask) commands in order and logs the masks,
/// answers UpdateQuery, gates Heartbeats by generation, refuses setpoints for lines it lacks, and
/// can reboot.
class TestBoard {
 public:
  TestBoard(uint32_t catalog_hash, uint16_t rx_buffer_bytes, uint32_t seed);
  /// Feeds bytes from the host; appends the board's frames to `out`.
  void Receive(const std::vector<uint8_t>& bytes, std::vector<std::vector<uint8_t>>& out);
  void Reboot();
  /// The session's host went silent for the board's timeout: the session ends (a new host's
  /// Hello is busy until then).
  void SilenceEndsTheSession() { session_.End(); }

  struct Applied {
    uint32_t boot_nonce;
    uint32_t command_id;
  };
  std::vector<Applied> applied;
  uint32_t boot_nonce() const { return session_.boot_nonce(); }
  uint32_t applied_heartbeat() const { return session_.heartbeat().applied(); }
  uint32_t sessions = 0;
  uint32_t closes = 0;                ///< sessions ended by their host's Close
  std::atomic<uint32_t> releases{0};  ///< Release frames received
  /// Lines the board has: a setpoint for any other is refused, as the firmware refuses it.
  static constexpr uint8_t kLines = 4;
  /// SetLineSetpoints and SetFingerTargets received (read by tests while a link runs).
  std::atomic<uint32_t> stream_frames{0};
  /// Answers Close and Release unsupported, as a bootloader in recovery mode does.
  bool recovery = false;

 private:
  void Handle(const pp::Frame& frame, std::vector<std::vector<uint8_t>>& out);
  template <class M>
  void Reply(const M& m, uint8_t seq, uint8_t flags, std::vector<std::vector<uint8_t>>& out);

  uint32_t catalog_hash_;
  uint16_t rx_buffer_bytes_;
  std::mt19937 rng_;
  pp::BoardSession session_{0};
  pp::OwningFrameDecoder decoder_;
};

/// A host that opens a session, streams ClearFault commands with unique ids through the reliable
/// sender, and records every outcome; on a board reset it reports in-flight commands as unknown.
class TestHost {
 public:
  TestHost(uint32_t catalog_hash, uint32_t seed, uint8_t initial_seq);
  /// One step at now_us: handle board bytes, (re)send Hello, submit, transmit.
  void Step(uint64_t now_us, const std::vector<uint8_t>& from_board,
            const std::function<void(const uint8_t*, size_t)>& send);
  void QueueCommands(uint32_t first_id, uint32_t count);

  std::map<uint32_t, pp::Status> outcomes;  ///< command id → final status
  std::vector<uint32_t> submitted_order;
  uint32_t resets_seen = 0;
  uint32_t max_bytes_in_flight = 0;
  uint32_t window_full_refusals = 0;
  pp::HostSession session;
  pp::ReliableSender sender;
  size_t queued() const { return queue_.size(); }

 private:
  void OnFrame(const pp::Frame& frame);
  std::mt19937 rng_;
  uint8_t next_initial_seq_;
  uint64_t hello_sent_us_ = 0;
  uint32_t hello_nonce_ = 0;
  bool hello_in_flight_ = false;
  pp::OwningFrameDecoder decoder_;
  std::deque<uint32_t> queue_;
  uint64_t now_us_ = 0;
};

}  // namespace palpa::testing
