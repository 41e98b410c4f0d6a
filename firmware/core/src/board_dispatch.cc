// Command dispatch: session and reliable-channel rules from protocol/, then one handler per
// message; here the session and stream messages (configuration: board_config_dispatch.cc,
// updates: board_update_dispatch.cc). Handlers change state only through its owners.
#include "board_reports.h"
#include "palpa/core/board.h"
#include "palpa/core/update_engine.h"
#include "palpa/protocol/codec.h"

namespace palpa::core {

namespace flags = protocol::flags;
using protocol::MessageType;

void Board::Poll(uint64_t now_us) {
  uint8_t bytes[128];
  for (int round = 0; round < 8; ++round) {  // bounded: the tick must not wait on a flood
    const size_t n = io_.link.Read(bytes, sizeof(bytes));
    for (size_t i = 0; i < n; ++i) {
      if (decoder_.Process(bytes[i]) == protocol::FrameDecoder::Event::kFrame) {
        OnFrame(decoder_.frame(), now_us);
      }
    }
    if (n < sizeof(bytes)) break;
  }
  tx_.Flush(io_.link);
}

void Board::Answer(uint8_t type, uint8_t seq, uint8_t answer_flags, Status status,
                   uint32_t detail) {
  uint8_t* slot = tx_.ReserveAnswer();
  if (slot == nullptr) return;
  const uint8_t header_flags = static_cast<uint8_t>(answer_flags | flags::kFromBoard |
                                                    (supervisor_.latched ? flags::kFaulted : 0));
  protocol::Result<size_t> n = Status::kOk;
  if (status == Status::kOk) {
    n = protocol::EncodeMessageFrame(protocol::Ack{session_.boot_nonce(), type}, seq, header_flags,
                                     slot, protocol::kMaxFrameSize);
  } else {
    n = protocol::EncodeMessageFrame(protocol::Nack{session_.boot_nonce(), type, status, detail},
                                     seq, header_flags, slot, protocol::kMaxFrameSize);
  }
  if (n.ok()) tx_.CommitAnswer(n.value);
}

void Board::OnFrame(const protocol::Frame& frame, uint64_t now_us) {
  const protocol::Header& h = frame.header;
  const bool reliable = (h.flags & flags::kReliable) != 0;
  const uint8_t answer_flags = reliable ? flags::kReliable : 0;
  if ((h.flags & flags::kFromBoard) != 0) return;  // our own frames looped back: ignore
  // Recovery mode speaks the bootstrap set and nothing else (the control core is not trusted).
  if (identity_.recovery && !protocol::IsBootstrap(h.type))
    return Answer(h.type, h.seq, answer_flags, Status::kUnsupported, 0);
  const Status admitted = session_.Admit(h.type);
  if (admitted != Status::kOk) return Answer(h.type, h.seq, answer_flags, admitted, 0);
  // A frame proves its host alive only when it is fresh for the session: each handler says so
  // (session_.Heard); a repeat, a stale generation or another session's frame never does.

  protocol::ReliableReceiver& receiver = session_.receiver();
  if (reliable && h.type != static_cast<uint8_t>(MessageType::kHello)) {
    const protocol::CachedOutcome* cached = nullptr;
    switch (receiver.Classify(h.seq, &cached)) {
      case protocol::ReliableReceiver::Verdict::kApply:
        break;
      case protocol::ReliableReceiver::Verdict::kDuplicate:
        if (cached->data_reply) {
          Handle(frame, now_us);  // queries are read-only: answer with the current report
        } else {
          Answer(cached->type, h.seq, flags::kReliable, cached->status, cached->detail);
        }
        return;
      case protocol::ReliableReceiver::Verdict::kGap:
        return Answer(h.type, h.seq, flags::kReliable, Status::kSeqGap, receiver.expected());
      case protocol::ReliableReceiver::Verdict::kIgnore:
        return;
    }
  }
  const HandlerAnswer outcome = Handle(frame, now_us);
  if (reliable && h.type != static_cast<uint8_t>(MessageType::kHello)) {
    receiver.Complete(h.type, outcome.status, outcome.detail, outcome.replied);
    // Applied in sequence: the commanding host. Timed after the work, which may be long (an
    // erase of flash), so the silence it took is not the host's.
    session_.Heard(io_.clock.NowMicros());
    if (!outcome.replied) Answer(h.type, h.seq, flags::kReliable, outcome.status, outcome.detail);
  } else if (outcome.status != Status::kOk) {
    Answer(h.type, h.seq, 0, outcome.status, outcome.detail);
  }
}

Board::HandlerAnswer Board::Handle(const protocol::Frame& frame, uint64_t now_us) {
  HandlerAnswer outcome;
  protocol::FieldError error;
  const Status decoded = protocol::DispatchFrame(
      frame, [&](const auto& m, const protocol::Header& h) { outcome = Apply(m, h, now_us); },
      &error);
  if (decoded != Status::kOk) return {decoded, error.offset};
  return outcome;
}

Board::HandlerAnswer Board::Apply(const protocol::Hello& m, const protocol::Header& h,
                                  uint64_t now_us) {
  using Verdict = protocol::BoardSession::HelloVerdict;
  Verdict verdict = session_.OnHello(m, now_us);
  if (verdict == Verdict::kBusy && identity_.recovery) {
    // Recovery mode holds nothing for anyone (every line is safe): the newest host has it.
    session_.End();
    verdict = session_.OnHello(m, now_us);
  }
  // Another host's session is alive: refused, with the timeout after which a silent one ends.
  if (verdict == Verdict::kBusy) return {Status::kBusy, config_.live().board.host_timeout_us};
  if (verdict == Verdict::kOpened) {  // a new host inherits no actuation, and no update
    Hold();
    if (io_.update != nullptr) io_.update->LeaveUpdateMode();
  }
  reports::HelloReply(Reports(), m.host_nonce, h.seq);
  return {Status::kOk, 0, true};
}

Board::HandlerAnswer Board::Apply(const protocol::EStop&, const protocol::Header& h,
                                  uint64_t now_us) {
  // Latched before the Ack: a setpoint that follows the Ack is refused, not applied for the
  // moment until the next tick. The tick reports it (estop_requested_).
  LatchFault(supervisor_, protocol::Fault::kEStopCommand, now_us, 0);
  estop_requested_ = true;
  safe_ = true;  // Critical for safety: the next tick writes safe codes, this one already won't
  Hold();
  Answer(static_cast<uint8_t>(MessageType::kEStop), h.seq, 0, Status::kOk, 0);
  return {Status::kOk, 0, true};
}

Board::HandlerAnswer Board::Apply(const protocol::Close& m, const protocol::Header& h, uint64_t) {
  // Another session's Close, or one repeated after this one ended: that session is over.
  if (!session_.Owns(m.session)) return {Status::kNoSession};
  EndSession();  // a deliberate end: outputs safe, no fault, an update left resumable
  Answer(static_cast<uint8_t>(MessageType::kClose), h.seq, 0, Status::kOk, 0);
  return {Status::kOk, 0, true};
}

Board::HandlerAnswer Board::Apply(const protocol::Release& m, const protocol::Header& h, uint64_t) {
  if (!session_.Owns(m.session)) return {Status::kNoSession};
  Hold();  // outputs safe until the host sends new setpoints or targets; no fault
  safe_ = true;
  Answer(static_cast<uint8_t>(MessageType::kRelease), h.seq, 0, Status::kOk, 0);
  return {Status::kOk, 0, true};
}

Board::HandlerAnswer Board::Apply(const protocol::Heartbeat& m, const protocol::Header&,
                                  uint64_t now_us) {
  // Only a newer generation of this session's heartbeat: a repeated or foreign one, however
  // often it comes, keeps nothing alive.
  if (session_.Owns(m.session) && session_.heartbeat().Accept(m.generation)) session_.Heard(now_us);
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::SetLineSetpoints& m, const protocol::Header&,
                                  uint64_t now_us) {
  if (!session_.Owns(m.session)) return {};  // another session's: dropped, as a stale one
  if (supervisor_.latched != 0) return {Status::kFaulted, supervisor_.latched};
  if (io_.update != nullptr && io_.update->in_update_mode()) return {Status::kBusy, 0};
  if (!session_.setpoints().WouldAccept(m.generation)) return {};  // stale: dropped silently
  uint32_t detail = 0;
  const Status status = lines_.Accept(m, fingers_, detail);
  if (status != Status::kOk) return {status, detail};
  session_.setpoints().Accept(m.generation);
  released_ = true;
  session_.Heard(now_us);
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::SetFingerTargets& m, const protocol::Header&,
                                  uint64_t now_us) {
  if (!session_.Owns(m.session)) return {};
  if (supervisor_.latched != 0) return {Status::kFaulted, supervisor_.latched};
  if (io_.update != nullptr && io_.update->in_update_mode()) return {Status::kBusy, 0};
  if (!session_.targets().WouldAccept(m.generation)) return {};
  uint32_t detail = 0;
  const Status status = fingers_.Accept(m, detail);
  if (status != Status::kOk) return {status, detail};
  session_.targets().Accept(m.generation);
  released_ = true;
  session_.Heard(now_us);
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::SetFingerMode& m, const protocol::Header&,
                                  uint64_t) {
  uint32_t detail = 0;
  const Status status = fingers_.SetMode(m, lines_, detail);
  return {status, detail};
}

}  // namespace palpa::core
