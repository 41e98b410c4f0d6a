// The C ABI over the device API: opaque handles, status codes, messages kept per handle.
#include "palpa/c/palpa.h"

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "palpa/host/device.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

struct palpa_device {
  std::unique_ptr<ph::Device> device;
  std::string error;
  std::mutex mutex;
  std::condition_variable arrived;
  std::deque<palpa_sample> samples;
  int subscription = 0;
};

namespace {

thread_local std::string g_open_error;
constexpr size_t kMaxQueuedSamples = 65536;

int Report(palpa_device* d, const ph::Outcome& o) {
  if (!o.ok()) d->error = o.message;
  return static_cast<int>(o.status);
}

int Set(palpa_device* d, uint8_t finger, ph::TargetKind kind, double value) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  return Report(d, d->device->Set({ph::FingerRequest{finger, ph::Request{kind, value}}}));
}

}  // namespace

extern "C" {

int palpa_open(const char* uri, palpa_device** out) {
  if (out == nullptr || uri == nullptr) {
    g_open_error = "palpa_open: uri and out must not be NULL";
    return static_cast<int>(pp::Status::kInvalidArgument);
  }
  *out = nullptr;
  std::string error;
  auto device = ph::Device::Open(uri, ph::DeviceOptions{}, &error);
  if (!device.ok()) {
    g_open_error = error;
    return static_cast<int>(device.status);
  }
  auto* d = new palpa_device();
  d->device = std::move(device.value);
  d->subscription = d->device->Subscribe([d](const ph::TelemetryFrame& f) {
    std::lock_guard<std::mutex> lock(d->mutex);
    const pp::Telemetry& t = f.telemetry;
    for (uint8_t tick = 0; tick < t.tick_count; ++tick) {
      palpa_sample s{};
      s.board_time_us = t.first_sample_us + static_cast<uint64_t>(tick) * t.sample_interval_us;
      s.host_time_s = f.host_time_s + static_cast<double>(tick) * t.sample_interval_us / 1e6;
      s.line_count = t.line_count;
      s.fault_bitmap = t.fault_bitmap;
      for (uint8_t i = 0; i < t.line_count && i < PALPA_MAX_LINES; ++i) {
        const pp::LineSample& l = t.samples[tick * t.line_count + i];
        s.setpoint_pa[i] = l.setpoint_pa;
        s.measured_pa[i] = l.measured_pa;
        s.command_counts[i] = l.command_counts;
        s.status[i] = l.status;
      }
      if (d->samples.size() >= kMaxQueuedSamples) d->samples.pop_front();
      d->samples.push_back(s);
    }
    d->arrived.notify_all();
  });
  *out = d;
  return PALPA_OK;
}

void palpa_close(palpa_device* d) {
  if (d == nullptr) return;
  d->device->Unsubscribe(d->subscription);
  d->device.reset();
  delete d;
}

const char* palpa_last_error(const palpa_device* d) {
  return d == nullptr ? g_open_error.c_str() : d->error.c_str();
}

const char* palpa_status_name(int status) {
  return pp::StatusName(static_cast<pp::Status>(status));
}

int palpa_get_info(palpa_device* d, palpa_info* info) {
  if (d == nullptr || info == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  const pp::HelloReply b = d->device->info();
  std::memset(info, 0, sizeof(*info));
  info->board_id = b.board_id;
  info->firmware_major = b.firmware_major;
  info->firmware_minor = b.firmware_minor;
  info->firmware_patch = b.firmware_patch;
  info->board_kind = static_cast<uint8_t>(b.board_kind);
  info->catalog_hash = b.catalog_hash;
  info->catalog_matches = d->device->link().catalog_matches() ? 1 : 0;
  info->plant_simulated = b.plant_simulated ? 1 : 0;
  info->time_scale = b.time_scale;
  std::memcpy(info->config_name, b.config_name.data(), b.config_name.size());
  info->line_count = b.line_count;
  info->finger_count = b.finger_count;
  for (uint8_t f = 0; f < b.finger_count; ++f)
    info->finger_kind[f] = static_cast<uint8_t>(b.fingers[f].kind);
  info->fault_bitmap = b.fault_bitmap;
  return PALPA_OK;
}

int palpa_set_level(palpa_device* d, uint8_t finger, int level) {
  return Set(d, finger, ph::TargetKind::kLevel, level);
}
int palpa_set_normalized(palpa_device* d, uint8_t finger, double v) {
  return Set(d, finger, ph::TargetKind::kNormalized, v);
}
int palpa_set_stiffness(palpa_device* d, uint8_t finger, double v) {
  return Set(d, finger, ph::TargetKind::kStiffnessNPerMm, v);
}
int palpa_set_deformation(palpa_device* d, uint8_t finger, double v) {
  return Set(d, finger, ph::TargetKind::kDeformationMm, v);
}
int palpa_set_pressure(palpa_device* d, uint8_t finger, double v) {
  return Set(d, finger, ph::TargetKind::kPressureKpa, v);
}

int palpa_estop(palpa_device* d) {
  return d == nullptr ? static_cast<int>(pp::Status::kInvalidArgument)
                      : Report(d, d->device->EStop());
}
int palpa_clear_fault(palpa_device* d) {
  return d == nullptr ? static_cast<int>(pp::Status::kInvalidArgument)
                      : Report(d, d->device->ClearFault());
}

int palpa_read_samples(palpa_device* d, palpa_sample* out, int capacity, int timeout_ms) {
  if (d == nullptr || out == nullptr || capacity <= 0)
    return -static_cast<int>(pp::Status::kInvalidArgument);
  std::unique_lock<std::mutex> lock(d->mutex);
  d->arrived.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                      [&] { return !d->samples.empty(); });
  int n = 0;
  while (n < capacity && !d->samples.empty()) {
    out[n++] = d->samples.front();
    d->samples.pop_front();
  }
  return n;
}

int palpa_record_start(palpa_device* d, const char* path) {
  if (d == nullptr || path == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  return Report(d, d->device->StartRecording(path));
}

int palpa_record_stop(palpa_device* d) {
  return d == nullptr ? static_cast<int>(pp::Status::kInvalidArgument)
                      : Report(d, d->device->StopRecording());
}

}  // extern "C"
