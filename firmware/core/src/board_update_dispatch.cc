// The update set's handlers: the board's side of `palpa flash` (DESIGN §9). Lines go safe on
// Enter and stay safe (Tick holds them) until the reboot.
#include "board_dispatch.h"

#include "palpa/core/board_reports.h"
#include "palpa/core/update_engine.h"

namespace palpa::core {

Outcome BoardDispatch::Apply(const protocol::UpdateEnter& m, const protocol::Header&) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  b_.Hold();
  b_.safe_ = true;  // this tick already: outputs go safe before anything is erased
  uint32_t detail = 0;
  const Status s = b_.io_.update->Enter(m, &detail);
  return {s, detail};
}

Outcome BoardDispatch::Apply(const protocol::UpdateErase& m, const protocol::Header&) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = b_.io_.update->Erase(m, &detail);
  return {s, detail};
}

Outcome BoardDispatch::Apply(const protocol::UpdateWrite& m, const protocol::Header&) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = b_.io_.update->Write(m, &detail);
  return {s, detail};
}

Outcome BoardDispatch::Apply(const protocol::UpdateQuery& m, const protocol::Header& h) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  BoardReports::UpdateStatus(b_, b_.io_.update->Query(m.slot), h.seq);
  return {Status::kOk, 0, true};
}

Outcome BoardDispatch::Apply(const protocol::UpdateActivate& m, const protocol::Header&) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = b_.io_.update->Activate(m, &detail);
  return {s, detail};
}

Outcome BoardDispatch::Apply(const protocol::UpdateReboot&, const protocol::Header&) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  b_.Hold();
  b_.safe_ = true;
  b_.reboot_requested_ = true;  // the shell resets once the Ack is out
  return {};
}

Outcome BoardDispatch::Apply(const protocol::UpdateConfirm& m, const protocol::Header&) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  uint32_t detail = 0;
  const Status s = b_.io_.update->Confirm(m, &detail);
  return {s, detail};
}

Outcome BoardDispatch::Apply(const protocol::SlotsQuery&, const protocol::Header& h) {
  if (b_.io_.update == nullptr) return {Status::kUnsupported};
  BoardReports::Slots(b_, b_.io_.update->Slots(), h.seq);
  return {Status::kOk, 0, true};
}

}  // namespace palpa::core
