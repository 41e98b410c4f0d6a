// The C ABI's handle on a board behind palpa serve: opened, and its telemetry queued as samples.
#include <algorithm>
#include <memory>
#include <mutex>

#include "c_api_device.h"

namespace ph = palpa::host;

namespace palpa::c_api {

host::Result<palpa_device*> OpenServed(const std::string& uri) {
  auto served = ph::ServedDevice::Open(uri, "C program");
  if (!served.ok()) return served.outcome();
  bool catalog_matches = false;
  const auto board = served.value->Info(&catalog_matches);
  if (!board.ok()) return board.outcome();
  std::vector<uint8_t> units;
  for (uint8_t f = 0; f < board.value.finger_count; ++f) {
    units.push_back(board.value.fingers[f].kind == protocol::FingerKind::kJamming
                        ? PALPA_UNIT_N_PER_MM
                        : PALPA_UNIT_MM);
  }
  auto d = std::make_unique<palpa_device>();
  d->served = std::move(served.value);
  palpa_device* raw = d.get();
  // Every sample of a board at its default 1 kHz, as a local device queues them.
  const host::Outcome subscribed =
      d->served->SubscribeSamples(1000, [raw, units](const ph::ServedSample& in) {
        palpa_sample s{};
        s.board_time_us = in.board_time_us;
        s.host_time_s = in.host_time_s;
        s.line_count =
            static_cast<uint8_t>(std::min<size_t>(in.measured_pa.size(), PALPA_MAX_LINES));
        s.fault_bitmap = in.fault_bitmap;
        for (uint8_t i = 0; i < s.line_count; ++i) {
          s.setpoint_pa[i] = i < in.setpoint_pa.size() ? in.setpoint_pa[i] : 0;
          s.measured_pa[i] = in.measured_pa[i];
          s.status[i] = i < in.status.size() ? in.status[i] : 0;
        }
        s.finger_count = static_cast<uint8_t>(
            std::min({in.finger_output.size(), units.size(), size_t{PALPA_MAX_FINGERS}}));
        for (uint8_t i = 0; i < s.finger_count; ++i) {
          s.finger_output[i] = in.finger_output[i];
          s.finger_unit[i] = units[i];
        }
        std::lock_guard<std::mutex> lock(raw->mutex);
        QueueSample(raw, s);
        raw->arrived.notify_all();
      });
  if (!subscribed.ok()) return subscribed;
  return d.release();
}

}  // namespace palpa::c_api
