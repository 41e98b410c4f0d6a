// Telemetry for the server's subscribers: all of it kept, each subscriber thinned for a page.
#include "palpa/serve/telemetry_hub.h"

#include "palpa/host/bit_names.h"

namespace palpa::serve {

TelemetryHub::TelemetryHub(const protocol::HelloReply& board,
                           std::vector<host::FingerCurves> curves)
    : board_(board), curves_(std::move(curves)), ring_(kCapacity) {}

void TelemetryHub::OnFrame(const host::TelemetryFrame& frame) {
  const protocol::Telemetry& t = frame.telemetry;
  if (t.line_count != board_.line_count || t.line_count == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  for (uint8_t k = 0; k < t.tick_count; ++k) {
    Tick& tick = ring_[next_seq_ % kCapacity];
    tick.seq = next_seq_++;
    tick.board_time_us = t.first_sample_us + static_cast<uint64_t>(k) * t.sample_interval_us;
    tick.faults = t.fault_bitmap;
    for (uint8_t l = 0; l < t.line_count; ++l) tick.lines[l] = t.samples[k * t.line_count + l];
  }
}

uint64_t TelemetryHub::received() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return next_seq_ - 1;
}

void TelemetryHub::Start(Subscription& s) const {
  std::lock_guard<std::mutex> lock(mutex_);
  s.last_seq = next_seq_ - 1;
}

nlohmann::json TelemetryHub::Take(Subscription& s) {
  std::vector<Tick> picked;
  uint64_t newest_seq = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    newest_seq = next_seq_ - 1;
    if (newest_seq <= s.last_seq) return nullptr;
    uint64_t from = s.last_seq + 1;
    if (newest_seq - from + 1 > kCapacity) {
      overtaken_ += newest_seq - kCapacity + 1 - from;
      from = newest_seq - kCapacity + 1;
    }
    const uint64_t spacing_us = static_cast<uint64_t>(1e6 / s.sample_rate_hz);
    for (uint64_t seq = from; seq <= newest_seq; ++seq) {
      const Tick& tick = ring_[seq % kCapacity];
      // Thinned on the board's clock, so the page's samples are evenly spaced in board time.
      if (s.sent_any && tick.board_time_us < s.last_sent_us + spacing_us &&
          tick.board_time_us >= s.last_sent_us)
        continue;
      picked.push_back(tick);
      s.last_sent_us = tick.board_time_us;
      s.sent_any = true;
    }
  }
  s.last_seq = newest_seq;
  if (picked.empty()) return nullptr;
  nlohmann::json t_us = nlohmann::json::array(), setpoint = nlohmann::json::array(),
                 measured = nlohmann::json::array(), status = nlohmann::json::array(),
                 output = nlohmann::json::array();
  for (const Tick& tick : picked) {
    t_us.push_back(tick.board_time_us);
    nlohmann::json sp = nlohmann::json::array(), me = nlohmann::json::array(),
                   st = nlohmann::json::array();
    for (uint8_t l = 0; l < board_.line_count; ++l) {
      sp.push_back(tick.lines[l].setpoint_pa);
      me.push_back(tick.lines[l].measured_pa);
      st.push_back(tick.lines[l].status);
    }
    setpoint.push_back(std::move(sp));
    measured.push_back(std::move(me));
    status.push_back(std::move(st));
    output.push_back(host::EstimateFingerOutputs(board_, curves_, tick.lines.data()));
  }
  const Tick& newest = picked.back();
  return {{"subscription", s.id},
          {"board_time_us", newest.board_time_us},
          {"faults", host::FaultList(newest.faults)},
          {"fault_bitmap", newest.faults},
          {"samples",
           {{"board_time_us", std::move(t_us)},
            {"setpoint_pa", std::move(setpoint)},
            {"measured_pa", std::move(measured)},
            {"status_bits", std::move(status)},
            {"finger_output", std::move(output)}}}};
}

}  // namespace palpa::serve
