// A board's lines and fingers as JSON, numbered as people number them.
#include "palpa/host/board_json.h"

#include "palpa/host/bit_names.h"
#include "palpa/host/fault_text.h"
#include "palpa/host/field_text.h"

namespace palpa::host {

namespace pp = palpa::protocol;
using nlohmann::ordered_json;

ordered_json LinesJson(const pp::HelloReply& b, unsigned number_from) {
  ordered_json lines = ordered_json::array();
  for (uint8_t i = 0; i < b.line_count; ++i) {
    lines.push_back({{"line", i + number_from},
                     {"kind", pp::kLineKindNames[static_cast<int>(b.lines[i].kind)]},
                     {"sensor", b.lines[i].has_sensor},
                     {"limit_min_pa", b.lines[i].limit_min_pa},
                     {"limit_max_pa", b.lines[i].limit_max_pa}});
  }
  return lines;
}

ordered_json FingersJson(const pp::HelloReply& b, const std::vector<FingerCurves>* curves,
                         unsigned number_from) {
  ordered_json fingers = ordered_json::array();
  for (uint8_t f = 0; f < b.finger_count; ++f) {
    const pp::FingerSummary& finger = b.fingers[f];
    ordered_json j = {
        {"finger", f + number_from},
        {"kind", pp::kFingerKindNames[static_cast<int>(finger.kind)]},
        {"unit", OutputUnitName(finger.kind)},
        {"line_a", finger.line_a + number_from},
        {"line_b", finger.line_b == pp::kNoLine ? ordered_json(nullptr)
                                                : ordered_json(finger.line_b + number_from)}};
    if (curves != nullptr && f < curves->size()) j["curve"] = (*curves)[f].source;
    fingers.push_back(j);
  }
  return fingers;
}

ordered_json CurveWarningsJson(const std::vector<CurveWarning>& warnings, unsigned number_from) {
  ordered_json list = ordered_json::array();
  for (const CurveWarning& w : warnings) {
    list.push_back({{"finger", w.finger + number_from},
                    {"file", w.file},
                    {"board", w.board},
                    {"disagreement", w.overlap ? ordered_json(w.disagreement) : ordered_json()},
                    {"at_kpa", w.at_pa / 1000},
                    {"residual", w.residual},
                    {"unit", w.unit},
                    {"message", w.message}});
  }
  return list;
}

std::string ConfigStateText(const pp::Diagnostics& d) {
  if (!d.config_unsaved) return d.config_saved ? "saved" : "factory default";
  return d.config_saved ? "changed, not saved: a reset returns to the saved one"
                        : "changed, not saved: a reset returns to the factory default";
}

ordered_json BoardIdentityJson(const pp::HelloReply& b, const pp::Diagnostics& diag,
                               bool catalog_matches) {
  const std::string firmware = std::to_string(b.firmware_major) + "." +
                               std::to_string(b.firmware_minor) + "." +
                               std::to_string(b.firmware_patch);
  return {{"kind", pp::kBoardKindNames[static_cast<int>(b.board_kind)]},
          {"id", b.board_id},
          {"firmware", firmware},
          {"protocol", b.protocol_version},
          {"catalog_hash", b.catalog_hash},
          {"catalog_matches", catalog_matches},
          {"plant_simulated", b.plant_simulated},
          {"time_scale", b.time_scale},
          {"reset_cause", pp::kResetCauseNames[static_cast<int>(b.reset_cause)]},
          {"configuration", FieldText(b.config_name)},
          {"config_state", ConfigStateText(diag)},
          {"config_is_default", b.config_is_default},
          {"config_saved", diag.config_saved},
          {"config_unsaved", diag.config_unsaved},
          {"active_slot", b.active_slot},
          {"rollback_counter", b.rollback_counter},
          {"host_timeout_us", b.host_timeout_us},
          {"faults", FaultList(diag.fault_bitmap)},
          {"fault_bitmap", diag.fault_bitmap}};
}

std::vector<int> ShapingFellBackLines(const pp::Diagnostics& diag, unsigned number_from) {
  std::vector<int> lines;
  for (int i = 0; i < pp::kMaxLines; ++i)
    if (diag.shaping_fallback_lines & (1u << i)) lines.push_back(i + static_cast<int>(number_from));
  return lines;
}

ordered_json DiagnosticsJson(const pp::Diagnostics& diag, const pp::LoopStats& s,
                             const LinkCounters& link, unsigned number_from) {
  ordered_json history = ordered_json::array();
  for (uint8_t i = 0; i < diag.history_count; ++i) {
    const auto& h = diag.history[i];
    history.push_back({{"time_us", h.time_us},
                       {"fault", FaultName(h.fault)},
                       {"detail", h.detail},
                       {"meaning", FaultDetail(h.fault, h.detail, static_cast<int>(number_from))}});
  }
  return {{"reset_cause", pp::kResetCauseNames[static_cast<int>(diag.reset_cause)]},
          {"boot_count", diag.boot_count},
          {"faults_latched", diag.fault_bitmap},
          {"faults_active", diag.active_conditions},
          {"faults_latched_names", FaultList(diag.fault_bitmap)},
          {"faults_active_names", FaultList(diag.active_conditions)},
          {"uptime_us", diag.uptime_us},
          {"shaping_fell_back", ShapingFellBackLines(diag, number_from)},
          {"history", history},
          {"loop",
           {{"ticks", s.ticks},
            {"period_us", s.period_us},
            {"jitter_max_us", s.jitter_max_us},
            {"worst_tick_us", s.worst_tick_us},
            {"mean_tick_us", s.mean_tick_us},
            {"overruns", s.overruns},
            {"telemetry_dropped", s.telemetry_dropped},
            {"rx_frames", s.rx_frames},
            {"rx_errors", s.rx_errors}}},
          {"link",
           {{"retransmissions", link.retransmissions},
            {"telemetry_lost", link.telemetry_lost},
            {"board_resets", link.board_resets}}}};
}

}  // namespace palpa::host
