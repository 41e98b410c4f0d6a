// The transfer of a firmware update: update mode, the slot erased, the image written in a window
// of chunks, and where to go on after the board reset or ended the session mid-write.
#include <algorithm>
#include <chrono>
#include <deque>
#include <optional>
#include <thread>

#include "flash_update.h"

namespace palpa::host::flash_internal {
namespace {

/// A command that did not complete because the session ended under it.
bool SessionLost(Status s) { return s == Status::kOutcomeUnknown || s == Status::kNoSession; }
constexpr int kMaxResumes = 3;

/// Where to go on writing after the session ended mid-write: once the link has a session again,
/// update mode anew and the board's written prefix if it is the image's (else from 0, erased
/// again). Empty when the board cannot be reached or refuses.
std::optional<uint32_t> ResumePoint(Link& link, uint8_t slot, const std::vector<uint8_t>& image,
                                    const FlashOptions& o) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!link.session_open()) {
    if (link.ended() || std::chrono::steady_clock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const auto size = static_cast<uint32_t>(image.size());
  if (link.Command(pp::UpdateEnter{slot, size}).status != Status::kOk) return std::nullopt;
  pp::UpdateStatus st{};
  const CommandResult q = link.Command(pp::UpdateQuery{slot});
  if (q.status == Status::kOk && q.Reply(st) && st.written_bytes <= size && st.written_bytes > 0 &&
      st.written_sha256 == pp::Sha256Of(image.data(), st.written_bytes)) {
    return st.written_bytes;
  }
  if (link.Command(pp::UpdateErase{slot, 0, size}, o.erase_timeout_ms).status != Status::kOk)
    return std::nullopt;
  return 0;
}

}  // namespace

/// 1. Update mode (the board's lines go safe), and where to start: from what the board holds of
///    this image when resuming, else from 0 on an erased slot.
bool Update::Enter() {
  CommandResult r = link_.Command(pp::UpdateEnter{slot_, size_});
  if (r.status != Status::kOk) return Fail(r.status, "enter update mode: " + Why(r));
  if (o_.resume) {
    pp::UpdateStatus st{};
    r = link_.Command(pp::UpdateQuery{slot_});
    if (r.status == Status::kOk && r.Reply(st) && st.written_bytes <= size_ &&
        st.written_sha256 == pp::Sha256Of(image_.data(), st.written_bytes)) {
      start_ = st.written_bytes;  // what is there is this image's beginning: go on from it
    }
  }
  report_.resumed_from = start_;
  if (start_ == 0) {
    Progress("erase", 0, 1, 0);
    r = link_.Command(pp::UpdateErase{slot_, 0, size_}, o_.erase_timeout_ms);
    if (r.status != Status::kOk) return Fail(r.status, "erase: " + Why(r));
    Progress("erase", 1, 1, 0);
  }
  return true;
}

/// 2. Write, contiguously, several chunks in the link's window at once (they arrive in order);
///    a Nack at the wrong offset names the resume point.
bool Update::Write() {
  constexpr size_t kInFlight = 4;
  struct Flight {
    uint32_t ticket, at, size;
  };
  std::deque<Flight> flight;
  auto drain = [&] {
    for (const Flight& f : flight) link_.Await(f.ticket);
    flight.clear();
  };
  const auto began = std::chrono::steady_clock::now();
  for (uint32_t next = start_; next < size_ || !flight.empty();) {
    while (next < size_ && flight.size() < kInFlight) {
      pp::UpdateWrite w;
      w.slot = slot_;
      w.offset = next;
      w.data_size = static_cast<uint8_t>(std::min<uint32_t>(pp::kMaxUpdateChunk, size_ - next));
      std::copy(image_.begin() + next, image_.begin() + next + w.data_size, w.data.begin());
      flight.push_back({link_.Submit(w), next, w.data_size});
      next += w.data_size;
    }
    const Flight f = flight.front();
    flight.pop_front();
    const CommandResult r = link_.Await(f.ticket);
    if (r.status == Status::kOutOfRange && r.detail < f.at) {
      drain();  // the board has less than we thought (it reset): from there
      next = r.detail;
      continue;
    }
    if (SessionLost(r.status) && report_.resumed_after_session_loss < kMaxResumes) {
      drain();  // what the board holds decides where to go on
      if (const auto point = ResumePoint(link_, slot_, image_, o_)) {
        ++report_.resumed_after_session_loss;
        next = *point;
        continue;
      }
    }
    if (r.status != Status::kOk) {
      drain();
      report_.write_seconds = Since(began);
      return Fail(r.status, "write at " + std::to_string(f.at) + " of " + std::to_string(size_) +
                                ": " + Why(r) +
                                "; run again with --resume to go on from what the board has");
    }
    report_.bytes_written += f.size;
    Progress("write", f.at + f.size, size_, Since(began));
  }
  report_.write_seconds = Since(began);
  return true;
}

}  // namespace palpa::host::flash_internal
