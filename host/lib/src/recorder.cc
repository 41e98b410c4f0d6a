// Recording telemetry to CSV with a JSON header; the file appears complete or not at all.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "palpa/hal/linux/atomic_file.h"
#include "palpa/host/device.h"

namespace palpa::host {

Outcome Device::StartRecording(const std::string& path) {
  std::lock_guard<std::mutex> lock(record_mutex_);
  if (record_) return Outcome{Status::kBusy, "already recording to " + record_path_, {}};
  auto file = std::make_unique<hal::linux_files::AtomicFile>();
  std::string error;
  if (!file->Open(path, &error)) return Outcome{Status::kIoError, error, {}};
  record_ = std::move(file);
  record_path_ = path;
  const pp::HelloReply b = link_->board();
  nlohmann::ordered_json header;
  header["format"] = "palpa recording 1";
  header["board"] = {
      {"kind", pp::kBoardKindNames[static_cast<int>(b.board_kind)]},
      {"id", b.board_id},
      {"firmware", std::to_string(b.firmware_major) + "." + std::to_string(b.firmware_minor) + "." +
                       std::to_string(b.firmware_patch)},
      {"catalog_hash", b.catalog_hash},
      {"plant_simulated", b.plant_simulated},
      {"time_scale", b.time_scale}};
  header["configuration"] = std::string(b.config_name.data());
  nlohmann::ordered_json lines = nlohmann::ordered_json::array();
  for (uint8_t i = 0; i < b.line_count; ++i) {
    lines.push_back({{"line", i},
                     {"kind", pp::kLineKindNames[static_cast<int>(b.lines[i].kind)]},
                     {"limit_min_pa", b.lines[i].limit_min_pa},
                     {"limit_max_pa", b.lines[i].limit_max_pa}});
  }
  header["lines"] = lines;
  header["units"] = {{"host_time_s", "s, host steady clock"},
                     {"board_time_us", "us, board clock"},
                     {"setpoint_pa", "Pa"},
                     {"measured_pa", "Pa"},
                     {"command_counts", "DAC counts"},
                     {"status", "line status bits (docs/protocol.md)"}};
  header["clock"] = {{"host_time_s", "board_time_us / 1e6 / time_scale + offset_s"},
                     {"offset_s", link_->BoardToHostSeconds(0)}};
  record_->Write("# " + header.dump() + "\n");
  record_->Write("host_time_s,board_time_us,line,setpoint_pa,measured_pa,command_counts,status\n");
  record_subscription_ = link_->Subscribe([this](const TelemetryFrame& f) {
    std::lock_guard<std::mutex> guard(record_mutex_);
    if (!record_) return;
    const pp::Telemetry& t = f.telemetry;
    char row[160];
    for (uint8_t tick = 0; tick < t.tick_count; ++tick) {
      const uint64_t board_us =
          t.first_sample_us + static_cast<uint64_t>(tick) * t.sample_interval_us;
      for (uint8_t line = 0; line < t.line_count; ++line) {
        const pp::LineSample& s = t.samples[tick * t.line_count + line];
        std::snprintf(row, sizeof(row), "%.6f,%llu,%u,%d,%d,%u,%u\n",
                      link_->BoardToHostSeconds(board_us),
                      static_cast<unsigned long long>(board_us), line, s.setpoint_pa, s.measured_pa,
                      s.command_counts, s.status);
        record_->Write(row);
      }
    }
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
  std::string error;
  const bool ok = record_->Commit(&error);
  record_.reset();
  return ok ? Outcome{} : Outcome{Status::kIoError, error, {}};
}

}  // namespace palpa::host
