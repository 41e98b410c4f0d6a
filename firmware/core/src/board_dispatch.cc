// Command dispatch: session and reliable-channel rules from protocol/, then one handler per
// message.
#include <cstring>

#include "board_dispatch.h"

#include "palpa/core/board_reports.h"
#include "palpa/core/update_engine.h"
#include "palpa/protocol/codec.h"
#include "palpa/protocol/crc32.h"

namespace palpa::core {

namespace flags = protocol::flags;

void Board::Poll(uint64_t now_us) {
  uint8_t bytes[128];
  BoardDispatch dispatch(*this);
  for (int round = 0; round < 8; ++round) {  // bounded: the tick must not wait on a flood
    const size_t n = io_.link.Read(bytes, sizeof(bytes));
    for (size_t i = 0; i < n; ++i) {
      if (decoder_.Process(bytes[i]) == protocol::FrameDecoder::Event::kFrame) {
        dispatch.OnFrame(decoder_.frame(), now_us);
      }
    }
    if (n < sizeof(bytes)) break;
  }
  tx_.Flush(io_.link);
}

void BoardDispatch::Answer(uint8_t type, uint8_t seq, uint8_t answer_flags, Status status,
                           uint32_t detail) {
  uint8_t* slot = b_.tx_.ReserveAnswer();
  if (slot == nullptr) return;
  const uint8_t header_flags = static_cast<uint8_t>(answer_flags | flags::kFromBoard |
                                                    (b_.supervisor_.latched ? flags::kFaulted : 0));
  protocol::Result<size_t> n = Status::kOk;
  if (status == Status::kOk) {
    n = protocol::EncodeMessageFrame(protocol::Ack{b_.session_.boot_nonce(), type}, seq,
                                     header_flags, slot, protocol::kMaxFrameSize);
  } else {
    n = protocol::EncodeMessageFrame(protocol::Nack{b_.session_.boot_nonce(), type, status, detail},
                                     seq, header_flags, slot, protocol::kMaxFrameSize);
  }
  if (n.ok()) b_.tx_.CommitAnswer(n.value);
}

void BoardDispatch::OnFrame(const protocol::Frame& frame, uint64_t now_us) {
  now_us_ = now_us;
  const protocol::Header& h = frame.header;
  const bool reliable = (h.flags & flags::kReliable) != 0;
  const uint8_t answer_flags = reliable ? flags::kReliable : 0;
  if ((h.flags & flags::kFromBoard) != 0) return;  // our own frames looped back: ignore
  // Recovery mode speaks the bootstrap set and nothing else (the control core is not trusted).
  if (b_.identity_.recovery && !protocol::IsBootstrap(h.type))
    return Answer(h.type, h.seq, answer_flags, Status::kUnsupported, 0);
  const Status admitted = b_.session_.Admit(h.type);
  if (admitted != Status::kOk) return Answer(h.type, h.seq, answer_flags, admitted, 0);
  // A frame proves its host alive only when it is fresh for the session: each handler says so
  // (HeardFromHost); a repeat, a stale generation or another session's frame never does.

  protocol::ReliableReceiver& receiver = b_.session_.receiver();
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
  const Outcome outcome = Handle(frame, now_us);
  if (reliable && h.type != static_cast<uint8_t>(MessageType::kHello)) {
    receiver.Complete(h.type, outcome.status, outcome.detail, outcome.replied);
    // Applied in sequence: the commanding host. Timed after the work, which may be long (an
    // erase of flash), so the silence it took is not the host's.
    b_.HeardFromHost(b_.io_.clock.NowMicros());
    if (!outcome.replied) Answer(h.type, h.seq, flags::kReliable, outcome.status, outcome.detail);
  } else if (outcome.status != Status::kOk) {
    Answer(h.type, h.seq, 0, outcome.status, outcome.detail);
  }
}

Outcome BoardDispatch::Handle(const protocol::Frame& frame, uint64_t now_us) {
  now_us_ = now_us;
  Outcome outcome;
  protocol::FieldError error;
  const Status decoded = protocol::DispatchFrame(
      frame, [&](const auto& m, const protocol::Header& h) { outcome = Apply(m, h); }, &error);
  if (decoded != Status::kOk) return {decoded, error.offset};
  return outcome;
}

Outcome BoardDispatch::Apply(const protocol::Hello& m, const protocol::Header& h) {
  using Verdict = protocol::BoardSession::HelloVerdict;
  Verdict verdict = b_.session_.OnHello(m);
  if (verdict == Verdict::kBusy && b_.identity_.recovery) {
    // Recovery mode holds nothing for anyone (every line is safe): the newest host has it.
    b_.session_.End();
    verdict = b_.session_.OnHello(m);
  }
  // Another host's session is alive: refused, with the timeout after which a silent one ends.
  if (verdict == Verdict::kBusy) return {Status::kBusy, b_.live_.board.host_timeout_us};
  if (verdict == Verdict::kOpened) {  // a new host inherits no actuation, and no update
    b_.Hold();
    if (b_.io_.update != nullptr) b_.io_.update->LeaveUpdateMode();
  }
  b_.last_host_frame_us_ = now_us_;
  BoardReports::HelloReply(b_, m.host_nonce, h.seq);
  return {Status::kOk, 0, true};
}

Outcome BoardDispatch::Apply(const protocol::EStop&, const protocol::Header& h) {
  // Latched before the Ack: a setpoint that follows the Ack is refused, not applied for the
  // moment until the next tick. The tick reports it (estop_requested_).
  LatchFault(b_.supervisor_, protocol::Fault::kEStopCommand, now_us_, 0);
  b_.estop_requested_ = true;
  b_.safe_ = true;  // Critical for safety: the next tick writes safe codes, this one already won't
  b_.Hold();
  Answer(static_cast<uint8_t>(MessageType::kEStop), h.seq, 0, Status::kOk, 0);
  return {Status::kOk, 0, true};
}

Outcome BoardDispatch::Apply(const protocol::Close& m, const protocol::Header& h) {
  // Another session's Close, or one repeated after this one ended: that session is over.
  if (!b_.session_.Owns(m.session)) return {Status::kNoSession};
  b_.EndSession();  // a deliberate end: outputs safe, no fault, an update left resumable
  Answer(static_cast<uint8_t>(MessageType::kClose), h.seq, 0, Status::kOk, 0);
  return {Status::kOk, 0, true};
}

Outcome BoardDispatch::Apply(const protocol::Release& m, const protocol::Header& h) {
  if (!b_.session_.Owns(m.session)) return {Status::kNoSession};
  b_.Hold();  // outputs safe until the host sends new setpoints or targets; no fault
  b_.safe_ = true;
  Answer(static_cast<uint8_t>(MessageType::kRelease), h.seq, 0, Status::kOk, 0);
  return {Status::kOk, 0, true};
}

Outcome BoardDispatch::Apply(const protocol::Heartbeat& m, const protocol::Header&) {
  // Only a newer generation of this session's heartbeat: a repeated or foreign one, however
  // often it comes, keeps nothing alive.
  if (b_.session_.Owns(m.session) && b_.session_.heartbeat().Accept(m.generation))
    b_.HeardFromHost(now_us_);
  return {};
}

Outcome BoardDispatch::Apply(const protocol::SetLineSetpoints& m, const protocol::Header&) {
  if (!b_.session_.Owns(m.session)) return {};  // another session's: dropped, as a stale one
  if (b_.supervisor_.latched != 0) return {Status::kFaulted, b_.supervisor_.latched};
  if (b_.io_.update != nullptr && b_.io_.update->in_update_mode()) return {Status::kBusy, 0};
  if (!b_.session_.setpoints().WouldAccept(m.generation)) return {};  // stale: dropped silently
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    const protocol::LineSetpoint& e = m.entries[i];
    if (e.line >= b_.live_.line_count) return {Status::kNotFound, i};
    const uint8_t owner = b_.line_owner_[e.line];
    if (owner != protocol::kNoLine && b_.finger_state_[owner].mode != protocol::FingerMode::kRaw) {
      return {Status::kWrongMode, i};
    }
    const LineParams& p = b_.line_params_[e.line];
    const float v = static_cast<float>(e.setpoint_pa);
    if (v < p.limit_min_pa || v > p.limit_max_pa) return {Status::kOutOfRange, i};
  }
  b_.session_.setpoints().Accept(m.generation);
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    b_.setpoint_pa_[m.entries[i].line] = static_cast<float>(m.entries[i].setpoint_pa);
  }
  b_.released_ = true;
  b_.HeardFromHost(now_us_);
  return {};
}

Outcome BoardDispatch::Apply(const protocol::SetFingerTargets& m, const protocol::Header&) {
  if (!b_.session_.Owns(m.session)) return {};
  if (b_.supervisor_.latched != 0) return {Status::kFaulted, b_.supervisor_.latched};
  if (b_.io_.update != nullptr && b_.io_.update->in_update_mode()) return {Status::kBusy, 0};
  if (!b_.session_.targets().WouldAccept(m.generation)) return {};
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    const protocol::FingerTarget& e = m.entries[i];
    if (e.finger >= b_.live_.finger_count) return {Status::kNotFound, i};
    const FingerParams& p = b_.finger_params_[e.finger];
    if (b_.finger_state_[e.finger].mode != protocol::FingerMode::kTarget)
      return {Status::kWrongMode, i};
    if (e.unit != UnitOf(p.kind)) return {Status::kBadValue, i};
    if (e.target > p.max_target) return {Status::kOutOfRange, i};
  }
  b_.session_.targets().Accept(m.generation);
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    b_.finger_state_[m.entries[i].finger].target = static_cast<float>(m.entries[i].target);
  }
  b_.released_ = true;
  b_.HeardFromHost(now_us_);
  return {};
}

Outcome BoardDispatch::Apply(const protocol::SetFingerMode& m, const protocol::Header&) {
  if (m.finger >= b_.live_.finger_count) return {Status::kNotFound, m.finger};
  FingerState& s = b_.finger_state_[m.finger];
  if (s.mode == m.mode) return {};
  s.mode = m.mode;
  const FingerParams& p = b_.finger_params_[m.finger];
  if (m.mode == protocol::FingerMode::kRaw) {
    // Raw setpoints start where the finger's lines are now, until the host sends its own.
    b_.setpoint_pa_[p.line_a] = b_.line_state_[p.line_a].slewed_pa;
    if (p.line_b != protocol::kNoLine)
      b_.setpoint_pa_[p.line_b] = b_.line_state_[p.line_b].slewed_pa;
  } else {
    RequireHoming(s);  // back to target mode: the compensator's memory is stale
  }
  b_.RefreshLineFlags();
  return {};
}

}  // namespace palpa::core
