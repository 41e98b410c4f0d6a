// The C ABI over the device API: opaque handles, status codes, messages kept per handle.
#include "palpa/c/palpa.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "c_api_device.h"
#include "palpa/calibration/calibrate_json.h"
#include "palpa/host/board_json.h"
#include "palpa/host/config_json.h"
#include "palpa/host/device.h"
#include "palpa/host/field_text.h"
#include "palpa/host/json_check.h"
#include "palpa/protocol/faults.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

thread_local std::string g_open_error;
constexpr size_t kMaxQueuedSamples = PALPA_SAMPLE_QUEUE_LIMIT;

using palpa::c_api::NotThroughServe;
using palpa::c_api::Report;

/// `text` into the caller's buffer (see palpa.h): kOverflow when it does not fit with its NUL.
int CopyText(const std::string& text, char* out, size_t capacity, size_t* length) {
  if (length != nullptr) *length = text.size();
  if (out == nullptr || text.size() >= capacity) return static_cast<int>(pp::Status::kOverflow);
  std::memcpy(out, text.c_str(), text.size() + 1);
  return PALPA_OK;
}

int Invalid(palpa_device* d, std::string message) {
  (d == nullptr ? g_open_error : d->error) = std::move(message);
  return static_cast<int>(pp::Status::kInvalidArgument);
}

int Set(palpa_device* d, uint8_t finger, ph::TargetKind kind, double value) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  const std::vector<ph::FingerRequest> request{{finger, ph::Request{kind, value}}};
  return Report(d, d->served ? d->served->Set(request) : d->device->Set(request));
}

}  // namespace

void palpa::c_api::QueueSample(palpa_device* d, const palpa_sample& s) {
  if (d->samples.size() >= kMaxQueuedSamples) {
    d->samples.pop_front();
    ++d->dropped;
  }
  d->samples.push_back(s);
}

extern "C" {

int palpa_open(const char* uri, palpa_device** out) {
  if (out == nullptr || uri == nullptr) {
    g_open_error = "palpa_open: uri and out must not be NULL";
    return static_cast<int>(pp::Status::kInvalidArgument);
  }
  *out = nullptr;
  if (std::strncmp(uri, "serve:", 6) == 0) {
    auto served = palpa::c_api::OpenServed(uri);
    if (!served.ok()) {
      g_open_error = served.message;
      return static_cast<int>(served.status);
    }
    *out = served.value;
    return PALPA_OK;
  }
  auto device = ph::Device::Open(uri, ph::DeviceOptions{});
  if (!device.ok()) {
    g_open_error = device.message;
    return static_cast<int>(device.status);
  }
  auto* d = new palpa_device();
  d->device = std::move(device.value);
  const pp::HelloReply board = d->device->info();
  for (uint8_t f = 0; f < board.finger_count; ++f) d->curves.push_back(d->device->curves(f));
  d->subscription = d->device->Subscribe([d, board](const ph::TelemetryFrame& f) {
    std::lock_guard<std::mutex> lock(d->mutex);
    const pp::Telemetry& t = f.telemetry;
    for (uint8_t tick = 0; tick < t.tick_count; ++tick) {
      palpa_sample s{};
      s.board_time_us = t.first_sample_us + static_cast<uint64_t>(tick) * t.sample_interval_us;
      s.host_time_s = f.host_time_s + static_cast<double>(tick) * t.sample_interval_us / 1e6;
      s.line_count = t.line_count;
      s.fault_bitmap = t.fault_bitmap;
      const pp::LineSample* lines = &t.samples[tick * t.line_count];
      for (uint8_t i = 0; i < t.line_count && i < PALPA_MAX_LINES; ++i) {
        s.setpoint_pa[i] = lines[i].setpoint_pa;
        s.measured_pa[i] = lines[i].measured_pa;
        s.command_counts[i] = lines[i].command_counts;
        s.status[i] = lines[i].status;
      }
      if (t.line_count == board.line_count) {
        const std::vector<double> outputs = ph::EstimateFingerOutputs(board, d->curves, lines);
        s.finger_count = static_cast<uint8_t>(outputs.size());
        for (uint8_t i = 0; i < s.finger_count && i < PALPA_MAX_FINGERS; ++i) {
          s.finger_output[i] = outputs[i];
          s.finger_unit[i] = board.fingers[i].kind == pp::FingerKind::kJamming ? PALPA_UNIT_N_PER_MM
                                                                               : PALPA_UNIT_MM;
        }
      }
      palpa::c_api::QueueSample(d, s);
    }
    d->arrived.notify_all();
  });
  *out = d;
  return PALPA_OK;
}

void palpa_close(palpa_device* d) {
  if (d == nullptr) return;
  if (d->served) {
    d->served.reset();  // control given up, its reader thread joined: before the queue goes
  } else {
    d->device->Unsubscribe(d->subscription);
    d->device->Close();  // the destructor would too; this way before the samples queue goes
    d->device.reset();
  }
  delete d;
}

const char* palpa_last_error(const palpa_device* d) {
  return d == nullptr ? g_open_error.c_str() : d->error.c_str();
}

uint32_t palpa_last_faults(const palpa_device* d) { return d == nullptr ? 0 : d->faults; }

const char* palpa_fault_name(int bit) {
  if (bit >= 0 && bit < static_cast<int>(pp::Fault::kCount)) return pp::kFaultNames[bit];
  thread_local std::string name;  // valid until this thread's next call
  name = "fault_" + std::to_string(bit);
  return name.c_str();
}

const char* palpa_status_name(int status) {
  return pp::StatusName(static_cast<pp::Status>(status));
}

int palpa_get_info(palpa_device* d, palpa_info* info) {
  if (d == nullptr || info == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  pp::HelloReply b;
  bool catalog_matches = false;
  if (d->served) {  // read now, so its faults are the latched ones
    auto served = d->served->Info(&catalog_matches);
    if (!served.ok()) return Report(d, served);
    b = served.value;
  } else {
    b = d->device->info();
    catalog_matches = d->device->link().catalog_matches();
  }
  std::memset(info, 0, sizeof(*info));
  info->board_id = b.board_id;
  info->firmware_major = b.firmware_major;
  info->firmware_minor = b.firmware_minor;
  info->firmware_patch = b.firmware_patch;
  info->board_kind = static_cast<uint8_t>(b.board_kind);
  info->catalog_hash = b.catalog_hash;
  info->catalog_matches = catalog_matches ? 1 : 0;
  info->plant_simulated = b.plant_simulated ? 1 : 0;
  info->time_scale = b.time_scale;
  const std::string name = ph::FieldText(b.config_name);
  std::memcpy(info->config_name, name.data(), std::min(name.size(), sizeof(info->config_name) - 1));
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
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  return Report(d, d->served ? d->served->EStop() : d->device->EStop());
}
int palpa_clear_fault(palpa_device* d) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  return Report(d, d->served ? d->served->ClearFault().outcome() : d->device->ClearFault());
}
int palpa_release(palpa_device* d) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  return Report(d, d->served ? d->served->Release() : d->device->Release());
}

int palpa_read_samples(palpa_device* d, palpa_sample* out, int capacity, int timeout_ms) {
  if (d == nullptr || out == nullptr || capacity <= 0 || timeout_ms < 0)
    return -static_cast<int>(pp::Status::kInvalidArgument);
  std::unique_lock<std::mutex> lock(d->mutex);
  if (timeout_ms > 0) {
    d->arrived.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                        [&] { return !d->samples.empty(); });
  }
  int n = 0;
  while (n < capacity && !d->samples.empty()) {
    out[n++] = d->samples.front();
    d->samples.pop_front();
  }
  return n;
}

uint64_t palpa_samples_dropped(const palpa_device* d) {
  if (d == nullptr) return 0;
  std::lock_guard<std::mutex> lock(d->mutex);
  return d->dropped;
}

int palpa_record_start(palpa_device* d, const char* path) {
  if (d == nullptr || path == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (d->served) return NotThroughServe(d, "palpa_record_start");
  return Report(d, d->device->StartRecording(path));
}

int palpa_record_stop(palpa_device* d) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (d->served) return NotThroughServe(d, "palpa_record_stop");
  return Report(d, d->device->StopRecording());
}

int palpa_config_read(palpa_device* d, char* out, size_t capacity, size_t* length) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  std::string text;
  if (d->served) {
    const auto config = d->served->ReadConfig();
    if (!config.ok()) return Report(d, config);
    text = config.value.dump();
  } else {
    const auto config = d->device->ReadConfig();
    if (!config.ok()) return Report(d, config);
    text = ph::ConfigToJson(config.value).dump();
  }
  const int status = CopyText(text, out, capacity, length);
  if (status != PALPA_OK) d->error = "palpa_config_read: the configuration does not fit the buffer";
  return status;
}

int palpa_config_apply(palpa_device* d, const char* json) {
  if (d == nullptr || json == nullptr)
    return Invalid(d, "palpa_config_apply: json must not be NULL");
  const auto patch = ph::ParseJson(json);
  if (!patch.ok())
    return Invalid(d, "palpa_config_apply: " + patch.message + " (nothing was sent)");
  if (d->served) return Report(d, d->served->ApplyConfig(patch.value, false));
  auto config = d->device->ReadConfig();
  if (!config.ok()) return Report(d, config);
  try {
    ph::ApplyConfigJson(patch.value, config.value);
  } catch (const std::exception& e) {
    return Invalid(d, std::string("palpa_config_apply: ") + e.what() + " (nothing was sent)");
  }
  return Report(d, d->device->ApplyConfig(config.value));
}

int palpa_config_save(palpa_device* d) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  return Report(d, d->served ? d->served->ApplyConfig(nlohmann::json::object(), true)
                             : d->device->SaveConfig());
}

int palpa_curve_warnings(palpa_device* d, char* out, size_t capacity, size_t* length) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (d->served) return NotThroughServe(d, "palpa_curve_warnings");
  const int status =
      CopyText(ph::CurveWarningsJson(d->device->curve_warnings(), 0).dump(), out, capacity, length);
  if (status != PALPA_OK) d->error = "palpa_curve_warnings: the warnings do not fit the buffer";
  return status;
}

int palpa_calibrate(palpa_device* d, const char* rig, const char* options_json, char* out,
                    size_t capacity, size_t* length) {
  if (rig == nullptr || options_json == nullptr)
    return Invalid(d, "palpa_calibrate: rig and options_json must not be NULL");
  if (d != nullptr && d->served) return NotThroughServe(d, "palpa_calibrate");
  const auto options = ph::ParseJson(options_json);
  if (!options.ok()) return Invalid(d, "palpa_calibrate: options: " + options.message);
  nlohmann::ordered_json summary;
  const ph::Outcome o = palpa::calibration::CalibrateFromJson(
      d == nullptr ? nullptr : d->device.get(), rig, options.value, &summary);
  if (!o.ok()) {
    (d == nullptr ? g_open_error : d->error) = o.message;
    return static_cast<int>(o.status);
  }
  const int status = CopyText(summary.dump(), out, capacity, length);
  if (status != PALPA_OK)
    (d == nullptr ? g_open_error : d->error) =
        "palpa_calibrate: the summary does not fit the buffer";
  return status;
}

}  // extern "C"
