// A board behind palpa serve: Device-like calls mapped onto the server's JSON-RPC methods.
#include "palpa/host/served_device.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>

#include "palpa/host/link.h"
#include "palpa/protocol/enums.h"

namespace palpa::host {
namespace {

using nlohmann::json;
using protocol::Status;

/// The unit names board.set takes, as the Python module's (TargetKind's order).
constexpr const char* kServeTargetKeys[] = {"level", "normalized", "n_per_mm", "mm", "kpa"};

/// `name`'s index in an enum's wire names, or `fallback` when the server names one this build
/// does not know.
template <class E>
E NamedEnum(const json& name, E fallback) {
  for (unsigned i = 0; i < static_cast<unsigned>(E::kCount); ++i) {
    if (name.is_string() && name.get<std::string>() == EnumNames(E{})[i]) return static_cast<E>(i);
  }
  return fallback;
}

template <class T>
std::vector<T> SampleRow(const json& table, size_t k) {
  std::vector<T> row;
  if (!table.is_array() || k >= table.size() || !table[k].is_array()) return row;
  for (const json& v : table[k]) row.push_back(v.is_number() ? v.get<T>() : T{});
  return row;
}

/// Each sample a notify_telemetry carries, `arrived_s` its arrival on the host's steady clock.
void ForEachSample(const json& n, double arrived_s,
                   const std::function<void(const ServedSample&)>& on_sample) {
  const json& p = n.value("params", json::object());
  const json& s = p.value("samples", json::object());
  const json& times = s.value("board_time_us", json::array());
  const json setpoints = s.value("setpoint_pa", json()), measured = s.value("measured_pa", json()),
             status = s.value("status_bits", json()), outputs = s.value("finger_output", json());
  const uint32_t faults = p.value("fault_bitmap", 0u);
  const uint64_t newest_us = p.value("board_time_us", uint64_t{0});
  for (size_t k = 0; k < times.size(); ++k) {
    ServedSample sample;
    sample.board_time_us = times[k].is_number_unsigned() ? times[k].get<uint64_t>() : 0;
    sample.host_time_s =
        arrived_s -
        static_cast<double>(newest_us - std::min(newest_us, sample.board_time_us)) / 1e6;
    sample.setpoint_pa = SampleRow<int32_t>(setpoints, k);
    sample.measured_pa = SampleRow<int32_t>(measured, k);
    sample.status = SampleRow<uint8_t>(status, k);
    sample.finger_output = SampleRow<double>(outputs, k);
    sample.fault_bitmap = faults;
    on_sample(sample);
  }
}

/// board.info's answer as the Hello it was made from (the fields it carries); json::exception
/// for an answer not shaped as the API says.
protocol::HelloReply HelloFromInfo(const json& info, bool* catalog_matches) {
  const json& b = info.value("board", json::object());
  protocol::HelloReply h{};
  h.board_kind = NamedEnum(b.value("kind", json()), protocol::BoardKind::kSim);
  h.board_id = b.value("id", 0u);
  unsigned major = 0, minor = 0, patch = 0;
  if (std::sscanf(b.value("firmware", std::string()).c_str(), "%u.%u.%u", &major, &minor, &patch) ==
      3) {
    h.firmware_major = static_cast<uint8_t>(major);
    h.firmware_minor = static_cast<uint8_t>(minor);
    h.firmware_patch = static_cast<uint8_t>(patch);
  }
  h.protocol_version = b.value("protocol", uint8_t{1});
  h.catalog_hash = b.value("catalog_hash", 0u);
  h.plant_simulated = b.value("plant_simulated", false);
  h.time_scale = b.value("time_scale", 1.0f);
  h.host_timeout_us = b.value("host_timeout_us", 0u);
  h.fault_bitmap = b.value("fault_bitmap", 0u);
  const std::string name = b.value("configuration", std::string());
  std::memcpy(h.config_name.data(), name.data(), std::min(name.size(), h.config_name.size()));
  const json& lines = info.value("lines", json::array());
  const json& fingers = info.value("fingers", json::array());
  h.line_count = static_cast<uint8_t>(std::min<size_t>(lines.size(), protocol::kMaxLines));
  for (uint8_t i = 0; i < h.line_count; ++i)
    h.lines[i].kind = NamedEnum(lines[i].value("kind", json()), protocol::LineKind::kPressure);
  h.finger_count = static_cast<uint8_t>(std::min<size_t>(fingers.size(), protocol::kMaxFingers));
  for (uint8_t f = 0; f < h.finger_count; ++f)
    h.fingers[f].kind =
        NamedEnum(fingers[f].value("kind", json()), protocol::FingerKind::kPneumatic);
  if (catalog_matches != nullptr) *catalog_matches = b.value("catalog_matches", false);
  return h;
}

}  // namespace

Result<std::unique_ptr<ServedDevice>> ServedDevice::Open(const std::string& uri,
                                                         const std::string& client_name) {
  auto client = ServeClient::Connect(uri);
  if (!client.ok()) return client.outcome();
  std::unique_ptr<ServedDevice> d(new ServedDevice());
  d->uri_ = uri;
  d->client_ = std::move(client.value);
  (void)d->client_->Call("server.connection.identify", {{"client_name", client_name}});
  auto info = d->client_->Call("board.info");
  if (!info.ok()) return Outcome::Fail(info.status, uri + ": " + info.message);
  if (!info.value.is_object() || !info.value.value("fingers", json()).is_array() ||
      !info.value.value("lines", json()).is_array() ||
      !info.value.value("board", json()).is_object())
    return Outcome::Fail(Status::kBadValue, uri + ": board.info's answer is not a board's");
  d->board_ = std::move(info.value);
  return d;
}

ServedDevice::~ServedDevice() {
  // Explicitly, as the server would on the disconnection anyway: the board is released now.
  if (controls_ && client_ != nullptr) (void)client_->Call("control.release", json::object(), 5);
  client_.reset();  // its reader thread ends before what a subscription's callback holds
}

Result<protocol::HelloReply> ServedDevice::Info(bool* catalog_matches) {
  auto info = client_->Call("board.info");
  if (!info.ok()) return info.outcome();
  try {
    return HelloFromInfo(info.value, catalog_matches);
  } catch (const json::exception& e) {
    return Outcome::Fail(Status::kBadValue,
                         uri_ + ": board.info's answer is not a board's (" + e.what() + ")");
  }
}

Outcome ServedDevice::CheckFingers(const std::vector<uint8_t>& fingers) const {
  const size_t count = board_["fingers"].size();
  for (const uint8_t f : fingers) {
    if (f >= count) {
      return Outcome::Fail(Status::kNotFound, "finger " + std::to_string(f) +
                                                  " does not exist (this board has fingers 0 to " +
                                                  std::to_string(count - 1) + ")");
    }
  }
  return {};
}

Outcome ServedDevice::TakeControl() {
  if (controls_) return {};
  const auto taken = client_->Call("control.take");
  if (!taken.ok()) return taken.outcome();
  controls_ = true;
  return {};
}

Outcome ServedDevice::Act(const std::string& method, const json& params) {
  if (const Outcome o = TakeControl(); !o.ok()) return o;
  const auto r = client_->Call(method, params);
  return r.ok() ? Outcome{} : r.outcome();
}

Outcome ServedDevice::Set(const std::vector<FingerRequest>& requests) {
  std::vector<uint8_t> fingers;
  json targets = json::array();
  for (const FingerRequest& r : requests) {
    fingers.push_back(r.finger);
    const json value = r.request.kind == TargetKind::kLevel
                           ? json(static_cast<int64_t>(r.request.value))
                           : json(r.request.value);
    targets.push_back(
        {{"finger", r.finger}, {kServeTargetKeys[static_cast<int>(r.request.kind)], value}});
  }
  if (const Outcome o = CheckFingers(fingers); !o.ok()) return o;
  return Act("board.set", {{"targets", targets}});
}

Outcome ServedDevice::EStop() {
  const auto r = client_->Call("board.estop");
  return r.ok() ? Outcome{} : r.outcome();
}

Result<std::vector<std::string>> ServedDevice::ClearFault() {
  if (const Outcome o = TakeControl(); !o.ok()) return o;
  const auto r = client_->Call("board.clear");
  if (!r.ok()) return r.outcome();
  std::vector<std::string> cleared;
  for (const json& name : r.value.value("cleared", json::array()))
    if (name.is_string()) cleared.push_back(name.get<std::string>());
  return cleared;
}

Outcome ServedDevice::Release() { return Act("board.release"); }

Result<json> ServedDevice::ReadConfig() { return client_->Call("board.config.read"); }

Outcome ServedDevice::ApplyConfig(const json& patch, bool save) {
  return Act("board.config.apply", {{"config", patch}, {"save", save}});
}

Outcome ServedDevice::SubscribeSamples(double sample_rate_hz,
                                       std::function<void(const ServedSample&)> on_sample) {
  client_->OnNotification([on_sample = std::move(on_sample)](const json& n) {
    if (n.value("method", "") != "notify_telemetry") return false;
    try {
      ForEachSample(n, SteadySeconds(), on_sample);
    } catch (const json::exception&) {
      // A notification not shaped as the server's API says: dropped, never the reader thread.
    }
    return true;
  });
  // 30 notifications a second, as the page and the Python module ask: each carries every sample
  // since the last.
  const auto sub = client_->Call("telemetry.subscribe",
                                 {{"updates_per_s", 30}, {"sample_rate_hz", sample_rate_hz}});
  return sub.ok() ? Outcome{} : sub.outcome();
}

}  // namespace palpa::host
