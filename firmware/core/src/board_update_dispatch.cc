// The update set's handlers: the board's side of `palpa flash` (DESIGN §9). Lines go safe on
// Enter and stay safe (Tick holds them) until the reboot.
#include "board_reports.h"
#include "palpa/core/board.h"
#include "palpa/core/update_engine.h"

namespace palpa::core {

Board::HandlerAnswer Board::Apply(const protocol::UpdateEnter& m, const protocol::Header&,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  Hold();
  safe_ = true;  // this tick already: outputs go safe before anything is erased
  uint32_t detail = 0;
  const Status s = io_.update->Enter(m, &detail);
  return {s, detail};
}

Board::HandlerAnswer Board::Apply(const protocol::UpdateErase& m, const protocol::Header&,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = io_.update->Erase(m, &detail);
  return {s, detail};
}

Board::HandlerAnswer Board::Apply(const protocol::UpdateWrite& m, const protocol::Header&,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = io_.update->Write(m, &detail);
  return {s, detail};
}

Board::HandlerAnswer Board::Apply(const protocol::UpdateQuery& m, const protocol::Header& h,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  reports::UpdateStatus(Reports(), io_.update->Query(m.slot), h.seq);
  return {Status::kOk, 0, true};
}

Board::HandlerAnswer Board::Apply(const protocol::UpdateActivate& m, const protocol::Header&,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = io_.update->Activate(m, &detail);
  return {s, detail};
}

Board::HandlerAnswer Board::Apply(const protocol::UpdateReboot&, const protocol::Header&,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  Hold();
  safe_ = true;
  reboot_requested_ = true;  // the shell resets once the Ack is out
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::UpdateConfirm& m, const protocol::Header&,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = io_.update->Confirm(m, &detail);
  return {s, detail};
}

Board::HandlerAnswer Board::Apply(const protocol::SlotsQuery&, const protocol::Header& h,
                                  uint64_t) {
  if (io_.update == nullptr) return {Status::kUnsupported};
  reports::Slots(Reports(), io_.update->Slots(), h.seq);
  return {Status::kOk, 0, true};
}

}  // namespace palpa::core
