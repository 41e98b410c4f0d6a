// Private to the core: the dispatcher's handlers, one per message, split over two files.
#pragma once

#include "palpa/core/board.h"
#include "palpa/protocol/catalog.h"

namespace palpa::core {

using protocol::MessageType;

/// The answer a handler gives: a status for Ack/Nack, or a report it has already queued.
struct Outcome {
  Status status = Status::kOk;
  uint32_t detail = 0;
  bool replied = false;  ///< a report went out instead of an Ack
};

class BoardDispatch {
 public:
  explicit BoardDispatch(Board& b) : b_(b) {}

  void OnFrame(const protocol::Frame& frame, uint64_t now_us);

 private:
  void Answer(uint8_t type, uint8_t seq, uint8_t answer_flags, Status status, uint32_t detail);
  Outcome Handle(const protocol::Frame& frame, uint64_t now_us);
  Outcome Apply(const protocol::Hello& m, const protocol::Header& h);
  Outcome Apply(const protocol::EStop&, const protocol::Header&);
  Outcome Apply(const protocol::Close& m, const protocol::Header& h);
  Outcome Apply(const protocol::Release& m, const protocol::Header& h);
  Outcome Apply(const protocol::Heartbeat& m, const protocol::Header&);
  Outcome Apply(const protocol::SetLineSetpoints& m, const protocol::Header&);
  Outcome Apply(const protocol::SetFingerTargets& m, const protocol::Header&);
  Outcome Apply(const protocol::SetFingerMode& m, const protocol::Header&);
  Outcome Apply(const protocol::ConfigureLine& m, const protocol::Header&);
  Outcome Apply(const protocol::ConfigureFinger& m, const protocol::Header&);
  Outcome Apply(const protocol::ConfigureBoard& m, const protocol::Header&);
  Outcome Apply(const protocol::StagedBegin& m, const protocol::Header&);
  Outcome Apply(const protocol::StagedPart& m, const protocol::Header&);
  Outcome Apply(const protocol::StagedCommit& m, const protocol::Header&);
  Outcome Apply(const protocol::GetConfig& m, const protocol::Header& h);
  Outcome Apply(const protocol::SaveConfig&, const protocol::Header&);
  Outcome Apply(const protocol::FactoryReset&, const protocol::Header&);
  Outcome Apply(const protocol::ClearFault& m, const protocol::Header&);
  Outcome Apply(const protocol::GetLoopStats&, const protocol::Header& h);
  Outcome Apply(const protocol::GetDiagnostics&, const protocol::Header& h);
  Outcome Apply(const protocol::UpdateEnter& m, const protocol::Header&);
  Outcome Apply(const protocol::UpdateErase& m, const protocol::Header&);
  Outcome Apply(const protocol::UpdateWrite& m, const protocol::Header&);
  Outcome Apply(const protocol::UpdateQuery& m, const protocol::Header& h);
  Outcome Apply(const protocol::UpdateActivate& m, const protocol::Header&);
  Outcome Apply(const protocol::UpdateReboot&, const protocol::Header&);
  Outcome Apply(const protocol::UpdateConfirm& m, const protocol::Header&);
  Outcome Apply(const protocol::SlotsQuery&, const protocol::Header& h);
  /// Everything else: board-to-host messages.
  template <class M>
  Outcome Apply(const M&, const protocol::Header&) {
    return {Status::kUnsupported};
  }
  /// Validates candidate_ as a whole and makes it live, or leaves live_ untouched.
  Outcome Commit();

  Board& b_;
  uint64_t now_us_ = 0;
};

}  // namespace palpa::core
