// Recording telemetry to CSV with a JSON header; the file appears complete or not at all.
#include <chrono>
#include <cstdio>

#include "palpa/hal/linux/atomic_file.h"
#include "palpa/host/device.h"
#include "recording_format.h"

namespace palpa::host {

Outcome Device::StartRecording(const std::string& path, RecordLayout layout) {
  AttachCalibrations();  // the curves each finger's output is estimated through
  std::lock_guard<std::mutex> lock(record_mutex_);
  if (record_) return Outcome{Status::kBusy, "already recording to " + record_path_, {}};
  auto file = std::make_unique<hal::linux_files::AtomicFile>();
  const hal::Done opened = file->Open(path);
  if (!opened.ok()) return Outcome{opened.status, opened.message, {}};
  record_ = std::move(file);
  record_path_ = path;
  record_layout_ = layout;
  record_curves_ = curves_;
  const auto seconds = [](auto now) {
    return std::chrono::duration<double>(now.time_since_epoch()).count();
  };
  record_wall_minus_steady_s_ =
      seconds(std::chrono::system_clock::now()) - seconds(std::chrono::steady_clock::now());
  const pp::HelloReply b = link_->board();
  record_->Write("# " + recording::Header(b, layout, record_curves_).dump() + "\n");
  record_->Write(recording::Columns(b, layout) + "\n");
  record_subscription_ = link_->Subscribe([this, b](const TelemetryFrame& f) {
    std::lock_guard<std::mutex> guard(record_mutex_);
    if (!record_) return;
    const pp::Telemetry& t = f.telemetry;
    if (t.line_count != b.line_count) return;  // not this configuration's telemetry
    std::string rows;
    for (uint8_t tick = 0; tick < t.tick_count; ++tick) {
      const uint64_t board_us =
          t.first_sample_us + static_cast<uint64_t>(tick) * t.sample_interval_us;
      recording::AppendRows(rows, b, record_layout_,
                            link_->BoardToHostSeconds(board_us) + record_wall_minus_steady_s_,
                            board_us, t.fault_bitmap, &t.samples[tick * t.line_count],
                            record_curves_);
    }
    record_->Write(rows);
  });
  return {};
}

Outcome Device::StopRecording() {
  int subscription = 0;
  {
    std::lock_guard<std::mutex> lock(record_mutex_);
    if (!record_) return {};
    subscription = record_subscription_;
  }
  link_->Unsubscribe(subscription);
  std::lock_guard<std::mutex> lock(record_mutex_);
  const hal::Done committed = record_->Commit();
  record_.reset();
  return committed.ok() ? Outcome{} : Outcome{committed.status, committed.message, {}};
}

}  // namespace palpa::host
