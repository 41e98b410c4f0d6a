// The link's latest-wins streams (line setpoints, finger targets): each value sent at once and
// waited on until telemetry shows it applied; link_receive.cc resends it until then.
#include <chrono>

#include "palpa/host/link.h"

namespace palpa::host {

template <class M>
uint32_t Link::StreamLatest(Stream& stream, M m) {
  std::unique_lock<std::mutex> lock(mutex_);
  // A value asked for while the link opens a new session (the board reset, or ended a session
  // this host let go silent) goes into that session: a stream is never replayed into a new
  // session by itself, but this one the application asks for now.
  changed_.wait_for(lock, std::chrono::milliseconds(options_.command_timeout_ms),
                    [&] { return session_.open() || stop_ || !hello_wanted_; });
  m.session = session_.session_tag();
  m.generation = ++stream.generation;
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(m, 0, 0, frame, sizeof(frame));
  if (!n.ok() || !session_.open()) {  // nothing goes out without a session to carry it
    stream.refused = n.ok() ? Status::kNoSession : n.status;
    stream.refused_detail = 0;
    stream.refused_generation = m.generation;
    return m.generation;
  }
  stream.frame.assign(frame, frame + n.value);
  stream.active = true;
  stream.sent_s = SteadySeconds();
  WriteFrame(frame, n.value);
  return m.generation;
}

uint32_t Link::StreamSetpoints(pp::SetLineSetpoints m) { return StreamLatest(setpoints_, m); }

uint32_t Link::StreamTargets(pp::SetFingerTargets m) { return StreamLatest(targets_, m); }

uint32_t Link::targets_generation() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return targets_.generation;
}

Status Link::WaitApplied(bool setpoints, uint32_t generation, int timeout_ms, uint32_t* detail) {
  std::unique_lock<std::mutex> lock(mutex_);
  Stream& s = setpoints ? setpoints_ : targets_;
  Status result = Status::kTimeout;
  changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] {
    if (s.refused_generation == generation) {
      result = s.refused;
      if (detail != nullptr) *detail = s.refused_detail;
      return true;
    }
    if (s.applied == generation || pp::GenerationNewer(s.applied, generation)) {
      result = Status::kOk;
      return true;
    }
    if (stop_ || !session_.open()) {
      result = Status::kNoSession;
      return true;
    }
    return false;
  });
  return result;
}

Status Link::WaitSetpointsApplied(uint32_t generation, int timeout_ms, uint32_t* detail) {
  return WaitApplied(true, generation, timeout_ms, detail);
}
Status Link::WaitTargetsApplied(uint32_t generation, int timeout_ms, uint32_t* detail) {
  return WaitApplied(false, generation, timeout_ms, detail);
}

}  // namespace palpa::host
