// The host side of the protocol: a reader thread that never waits on the application, sessions
// (opened, closed, lost to another host), reliable commands, latest-wins streams resent until
// applied, heartbeats from their own thread, EStop and Release, telemetry to subscribers, and
// board time mapped to host time.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "palpa/host/command_result.h"
#include "palpa/host/host_timeout.h"
#include "palpa/host/link_options.h"
#include "palpa/host/transport.h"
#include "palpa/protocol/codec.h"
#include "palpa/protocol/reliable_sender.h"
#include "palpa/protocol/session.h"

namespace palpa::host {

namespace pp = palpa::protocol;

/// A telemetry frame as received, with the host time it maps to.
struct TelemetryFrame {
  pp::Telemetry telemetry;
  double host_time_s = 0;  ///< host steady-clock time of the first sample
};

struct LinkCounters {
  uint64_t frames = 0;
  uint64_t telemetry_frames = 0;
  uint64_t telemetry_lost = 0;      ///< frames missing in the sequence (link or board drops)
  uint64_t subscriber_dropped = 0;  ///< frames a slow subscriber never saw
  uint64_t framing_errors = 0;
  uint64_t retransmissions = 0;
  uint64_t board_resets = 0;
  uint64_t outcome_unknown = 0;
  uint64_t heartbeats = 0;
  uint64_t transport_lost = 0;  ///< the transport went away (unplugged, closed by the board)
  uint64_t reopens = 0;         ///< ... and was opened again
};

class Link {
 public:
  /// Opens a session over `transport` (Hello, with retries). A catalog mismatch still opens:
  /// then only the bootstrap set works, and catalog_matches() is false. A board whose session
  /// belongs to another host answers busy: the Hello is retried for as long as a silent host's
  /// session would take to end (the board's timeout), then Open fails with kBusy and "busy:
  /// another host holds the board".
  static Result<std::unique_ptr<Link>> Open(std::unique_ptr<Transport> transport,
                                            LinkOptions options);
  /// Closes the session (Close) and stops the link's threads.
  ~Link();
  Link(const Link&) = delete;
  Link& operator=(const Link&) = delete;

  pp::HelloReply board() const;
  bool catalog_matches() const;
  /// "host catalog 0x… (protocol 1) vs board catalog 0x… (firmware a.b.c, protocol 1)".
  std::string Versions() const;
  std::string Describe() const { return description_; }
  /// The board's host-silence timeout changed other than by a ConfigureBoard or a staged board
  /// record sent on this link (which the link follows itself), e.g. after a factory reset:
  /// heartbeats go at a quarter of it.
  void SetHostTimeout(uint32_t host_timeout_us);

  /// Sends a reliable command and waits for its Ack, Nack or report (`timeout_ms` < 0: the
  /// link's command timeout; an erase of flash gets a longer one).
  template <class M>
  CommandResult Command(const M& m, int timeout_ms = -1) {
    uint8_t packet[pp::kMaxPacketSize] = {};
    pp::FieldError field;
    const auto size = pp::EncodePacket(m, 0, 0, packet, sizeof(packet), &field);
    if (!size.ok()) {
      return CommandResult{size.status,
                           0,
                           0,
                           {},
                           std::string("cannot encode ") + M::kInfo.name + ": field " +
                               (field.field ? field.field : "?") + " is " +
                               pp::StatusName(size.status)};
    }
    return CommandPacket(static_cast<uint8_t>(M::kInfo.type), packet + pp::kHeaderSize,
                         size.value - pp::kHeaderSize, timeout_ms);
  }

  /// Queues a reliable command without waiting for its answer (commands go out in the order of
  /// the calls, several in the window); Await(ticket) gives the answer. A command that cannot be
  /// queued is answered at once.
  template <class M>
  uint32_t Submit(const M& m, int timeout_ms = -1) {
    uint8_t packet[pp::kMaxPacketSize] = {};
    pp::FieldError field;
    const auto size = pp::EncodePacket(m, 0, 0, packet, sizeof(packet), &field);
    if (!size.ok()) {
      return FailedTicket(CommandResult{size.status,
                                        0,
                                        0,
                                        {},
                                        std::string("cannot encode ") + M::kInfo.name + ": field " +
                                            (field.field ? field.field : "?") + " is " +
                                            pp::StatusName(size.status)});
    }
    return SubmitPacket(static_cast<uint8_t>(M::kInfo.type), packet + pp::kHeaderSize,
                        size.value - pp::kHeaderSize, timeout_ms);
  }
  CommandResult Await(uint32_t ticket, int timeout_ms = -1);

  /// Latest-wins streams: the link fills in the session and the generation, sends at once (once a
  /// session being reopened is open) and resends until telemetry shows it applied. Returns the
  /// generation.
  uint32_t StreamSetpoints(pp::SetLineSetpoints m);
  uint32_t StreamTargets(pp::SetFingerTargets m);
  /// The generation the targets stream last sent (0 before the first): what a caller that set
  /// fingers without waiting (a scene's Feed) matches telemetry or latency stamps against.
  uint32_t targets_generation() const;
  /// Waits until telemetry shows the generation applied (kOk), it is Nacked (the status, and in
  /// *detail the Nack's: the latched faults for kFaulted, the entry otherwise), or the timeout
  /// passes (kTimeout).
  Status WaitSetpointsApplied(uint32_t generation, int timeout_ms, uint32_t* detail = nullptr);
  Status WaitTargetsApplied(uint32_t generation, int timeout_ms, uint32_t* detail = nullptr);

  /// Sends EStop at once and repeats it until the board acknowledges (kOk) or gives up.
  Status EStop();

  /// Ends the session on purpose: streams stop, heartbeats stop, and Close is repeated until the
  /// board answers — every output safe within a tick, no fault latched, the board free for the
  /// next host. kOk once heard (an Ack; a no_session or a bootloader's unsupported count too);
  /// kTimeout when unanswered (the board's silence timeout ends the session instead);
  /// kCatalogMismatch: not sent, since that id may mean something else to other firmware
  /// (nothing was actuated; silence ends the session quietly). No reconnection follows; later
  /// commands fail with no_session. Called again, it returns at once.
  Status Close();
  /// Every output safe within a tick, no fault latched, the session kept (a server that stops
  /// actuating without leaving): streams stop being resent; new ones actuate again. kOk once the
  /// board acknowledged; a recovery-mode board's unsupported counts (its lines are safe).
  Status Release();

  /// Calls `callback` with every telemetry frame, on a thread of its own: a slow callback
  /// delays only itself (frames beyond the queue are dropped and counted).
  int Subscribe(std::function<void(const TelemetryFrame&)> callback);
  /// Once this returns the callback is neither running nor called again, so what it uses may go.
  /// Called from inside a callback it returns at once (that call finishes; no other follows).
  void Unsubscribe(int id);

  LinkCounters counters() const;
  /// Host steady-clock seconds at which the board's clock read `board_us`.
  double BoardToHostSeconds(uint64_t board_us) const;
  /// Events worth telling a person (board reset, outcome unknown, reconnects), oldest first.
  std::vector<std::string> TakeEvents();
  bool session_open() const;
  /// Why the session is not open (closed by this host, ended by the board, lost to another
  /// host), or empty while it is.
  std::string session_end() const;
  /// The session is over for good: closed by this host, or the board belongs to another host (a
  /// board that reset, ended a silent session, or was lost and is being reopened is reconnected to
  /// instead).
  bool ended() const;

 private:
  explicit Link(std::unique_ptr<Transport> transport, LinkOptions options);
  CommandResult CommandPacket(uint8_t type, const uint8_t* body, size_t size, int timeout_ms);
  uint32_t SubmitPacket(uint8_t type, const uint8_t* body, size_t size, int timeout_ms);
  uint32_t FailedTicket(CommandResult result);  ///< a ticket already answered with `result`
  static uint64_t Micros(double seconds) { return static_cast<uint64_t>(seconds * 1e6); }
  void ReaderLoop();
  /// The reader thread after its transport went away: reopens it (true) or ends the link.
  bool TransportLost();
  void HeartbeatLoop();
  void DispatchLoop();
  void OnFrame(const pp::Frame& frame, double now_s);
  void OnHelloReply(const pp::HelloReply& m);
  /// Our Hello refused because another host's session is alive: true when `m` was that refusal.
  bool OnHelloBusy(const pp::Nack& m, double now_s);
  /// The answer to an EStop, Close or Release (which are sent outside the sender's window).
  void OnUnsequencedAck(const pp::Ack& m);
  /// What a Nack means for the session and the streams: true when nothing more is to be done
  /// with it, false when it answers a reliable command (OnCommandAnswer).
  bool OnSessionNack(const pp::Nack& m, const pp::Header& h);
  /// An Ack, Nack or report answering the reliable command sent as `seq`: its ticket completes.
  void OnCommandAnswer(const pp::Frame& frame, uint8_t seq, Status status, uint32_t detail,
                       bool report, double now_s);
  void OnTelemetry(const pp::Telemetry& t, double now_s);
  void OnBoardReset(const std::string& why);
  /// The session ended without a board reset (the board ended it, another host holds the board,
  /// or this host closed it): what was in flight has an unknown outcome; `reconnect` opens anew.
  void EndSession(const std::string& why, bool reconnect);
  /// Sends an unsequenced session message (Close or Release) until `answered` (or the attempts
  /// are spent); mutex_ held by `lock`.
  template <class M>
  bool RepeatUntilAnswered(std::unique_lock<std::mutex>& lock, const M& m, bool& answered);
  void SendHello();
  void Service(double now_s);
  void WriteFrame(const uint8_t* frame, size_t size);
  template <class M>
  void SendUnsequenced(const M& m);
  Status WaitApplied(bool setpoints, uint32_t generation, int timeout_ms, uint32_t* detail);

  std::unique_ptr<Transport> transport_;  ///< replaced only by the reader, under write_mutex_
  const std::string description_;
  LinkOptions options_;
  std::mutex write_mutex_;
  mutable std::mutex mutex_;  ///< everything below
  std::condition_variable changed_;
  pp::HostSession session_;
  pp::ReliableSender sender_;
  uint32_t hello_nonce_ = 0;
  double hello_sent_s_ = -1;
  bool hello_wanted_ = true;
  HostTimeoutTracker host_timeout_;  ///< its changes wake the heartbeat loop
  CarriedHostTimeout carried_;       ///< the timeout commands carry, staged ones included
  struct Pending {
    bool done = false;
    CommandResult result;
  };
  std::map<uint32_t, Pending> pending_;
  uint32_t next_cookie_ = 1;
  struct Stream {
    bool active = false;
    uint32_t generation = 0;
    uint32_t applied = 0;
    Status refused = Status::kOk;
    uint32_t refused_detail = 0;
    uint32_t refused_generation = 0;
    double sent_s = 0;
    std::vector<uint8_t> frame;
  };
  Stream setpoints_, targets_;
  /// Both latest-wins streams: the next generation, encoded once, kept for retransmission.
  template <class M>
  uint32_t StreamLatest(Stream& stream, M m);
  uint32_t heartbeat_generation_ = 0;
  bool estop_acked_ = false;
  bool closed_ = false;     ///< Close() was called: no heartbeats, no reconnection
  bool reopening_ = false;  ///< a lost transport is being opened again: the link has not ended
  bool close_answered_ = false;
  bool release_answered_ = false;
  Status release_status_ = Status::kOk;
  /// Busy answers to our Hello: when the first came, and the board's host-silence timeout.
  double busy_since_s_ = -1;
  double last_board_frame_s_ = -1;  ///< when the board was last heard (any frame)
  uint32_t busy_timeout_us_ = 0;
  std::string session_end_;
  LinkCounters counters_;
  std::vector<std::string> events_;
  uint64_t expected_next_sample_us_ = 0;
  double min_offset_s_ = 1e300;  ///< host time minus board time, lower envelope
  double offset_window_start_s_ = 0;
  double window_min_offset_s_ = 1e300;
  // Subscribers and their queue.
  std::map<int, std::shared_ptr<std::function<void(const TelemetryFrame&)>>> subscribers_;
  int next_subscriber_ = 1;
  int running_subscriber_ = 0;  ///< whose callback the dispatcher is in (0: none)
  std::condition_variable callback_returned_;
  std::deque<TelemetryFrame> queue_;
  std::condition_variable queue_changed_;
  bool stop_ = false;
  std::thread reader_, heartbeat_, dispatcher_;
};

double SteadySeconds();

}  // namespace palpa::host
