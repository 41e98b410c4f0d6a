// The board through the host library, and the board's clock from its telemetry.
#include "palpa/calibration/device_rig.h"

#include <chrono>
#include <thread>

namespace palpa::calibration {

DeviceBoardPort::DeviceBoardPort(host::Device& device) : device_(device) {
  subscription_ = device_.Subscribe([this](const host::TelemetryFrame& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    const protocol::Telemetry& t = f.telemetry;
    // The newest tick's samples: one per line, the last `line_count` of the batch.
    for (uint8_t i = 0; i < t.line_count && i < protocol::kMaxLines; ++i) {
      measured_kpa_[i] = t.samples[t.sample_count - t.line_count + i].measured_pa / 1000.0;
    }
    faults_ = t.fault_bitmap;
    last_frame_s_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  });
}

DeviceBoardPort::~DeviceBoardPort() { device_.Unsubscribe(subscription_); }

bool DeviceBoardPort::jamming(uint8_t finger) {
  return device_.info().fingers[finger].kind == protocol::FingerKind::kJamming;
}

uint8_t DeviceBoardPort::driven_line(uint8_t finger) {
  const protocol::FingerSummary f = device_.info().fingers[finger];
  return f.kind == protocol::FingerKind::kJamming ? f.line_b : f.line_a;
}

RigStatus DeviceBoardPort::SetDrive(uint8_t finger, double kpa_a, double kpa_b) {
  const protocol::FingerSummary f = device_.info().fingers[finger];
  std::vector<std::pair<uint8_t, double>> lines = {{f.line_a, kpa_a}};
  if (f.line_b != protocol::kNoLine) lines.push_back({f.line_b, kpa_b});
  const host::Outcome o = device_.SetLines(lines, true);
  return o.ok() ? RigStatus{} : o;
}

RigStatus DeviceBoardPort::MeasuredKpa(uint8_t line, double* kpa) {
  std::lock_guard<std::mutex> lock(mutex_);
  *kpa = measured_kpa_[line];
  return {};
}

RigStatus DeviceBoardPort::LineRangeKpa(uint8_t line, double* kpa) {
  const auto read = device_.ReadLine(line);
  if (!read.ok()) return read.outcome();
  *kpa = std::max(std::abs(read.value.limit_min_pa), std::abs(read.value.limit_max_pa)) / 1000.0;
  return {};
}

RigStatus DeviceBoardPort::SetTrim(uint8_t line, bool on) {
  return Reconfigure(line, [on](protocol::ConfigureLine& c) {
    if (!on) c.trim_kp = c.trim_ki_per_s = 0;
  });
}

RigStatus DeviceBoardPort::SetBareLine(uint8_t line, bool bare) {
  return Reconfigure(line, [bare](protocol::ConfigureLine& c) {
    if (bare) MakeBare(c);
  });
}

RigStatus DeviceBoardPort::Reconfigure(uint8_t line,
                                       const std::function<void(protocol::ConfigureLine&)>& edit) {
  if (!known_[line]) {
    const auto read = device_.ReadLine(line);
    if (!read.ok()) return read.outcome();
    configured_[line] = read.value;
    known_[line] = true;
  }
  protocol::ConfigureLine c = configured_[line];
  edit(c);
  const host::Outcome o = device_.ConfigureLine(c);
  return o.ok() ? RigStatus{} : o;
}

RigStatus DeviceBoardPort::Faults(uint32_t* bitmap) {
  if (!device_.link().session_open())
    return RigStatus::Fail(Status::kUnavailable, "the board does not answer (no session)");
  std::lock_guard<std::mutex> lock(mutex_);
  const double now =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (last_frame_s_ > 0 && now - last_frame_s_ > 1.0)
    return RigStatus::Fail(Status::kUnavailable, "no telemetry from the board for over 1 s");
  *bitmap = faults_;
  return {};
}

RigStatus DeviceBoardPort::VentAll() {
  std::vector<std::pair<uint8_t, double>> lines;
  for (uint8_t i = 0; i < device_.info().line_count; ++i) lines.push_back({i, 0.0});
  const host::Outcome o = device_.SetLines(lines, false);
  return o.ok() ? RigStatus{} : o;
}

BoardTime::BoardTime(host::Device& device)
    : device_(device), scale_(device.info().time_scale > 0 ? device.info().time_scale : 1.0) {
  subscription_ = device_.Subscribe([this](const host::TelemetryFrame& f) {
    const protocol::Telemetry& t = f.telemetry;
    const uint64_t newest_us =
        t.first_sample_us + (t.tick_count > 0 ? (t.tick_count - 1u) * t.sample_interval_us : 0);
    std::lock_guard<std::mutex> lock(mutex_);
    // A board that restarted counts from 0 again: time since the first frame goes on from there.
    if (seen_ && newest_us > last_us_) elapsed_us_ += newest_us - last_us_;
    seen_ = true;
    last_us_ = newest_us;
    if (elapsed_us_ >= wake_at_us_) advanced_.notify_all();  // not for every frame: a few kHz
  });
}

BoardTime::~BoardTime() { device_.Unsubscribe(subscription_); }

double BoardTime::Now() {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<double>(elapsed_us_) / 1e6;
}

void BoardTime::Wait(double seconds) {
  const auto real = std::chrono::duration<double>(seconds / scale_);
  std::unique_lock<std::mutex> lock(mutex_);
  if (!seen_) {
    lock.unlock();
    std::this_thread::sleep_for(real);
    return;
  }
  const uint64_t until_us = elapsed_us_ + static_cast<uint64_t>(seconds * 1e6 + 0.5);
  wake_at_us_ = until_us;
  // Bounded by the clock's progress, not by a deadline in real time: a loaded machine slows
  // palpa-sim's clock (it slips, and holds short of the host-silence deadline while the host is
  // descheduled), and a dwell cut short would leave the film still moving when it is touched.
  uint64_t last_look_us = elapsed_us_;
  while (
      !advanced_.wait_for(lock, std::chrono::seconds(1), [&] { return elapsed_us_ >= until_us; })) {
    if (elapsed_us_ == last_look_us) break;  // stopped for a second: the rig's checks say why
    last_look_us = elapsed_us_;
  }
  wake_at_us_ = UINT64_MAX;
}

}  // namespace palpa::calibration
