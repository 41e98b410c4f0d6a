// Writes tests/protocol/golden_frames.json: sample frames of every message type and edge cases.
// The file is reviewed and committed; tests read it back as the frozen truth.
#include <cstdio>
#include <fstream>
#include <iostream>

#include "palpa/host/json_fields.h"
#include "palpa/protocol/codec.h"

namespace pp = palpa::protocol;
using palpa::host::json;

namespace {

nlohmann::ordered_json frames = nlohmann::ordered_json::array();

template <class M>
void Add(const std::string& name, const M& m, uint8_t seq, uint8_t flags) {
  uint8_t frame[pp::kMaxFrameSize];
  pp::FieldError error;
  const auto size = pp::EncodeMessageFrame(m, seq, flags, frame, sizeof(frame), &error);
  if (!size.ok()) {
    std::cerr << name << ": cannot encode (" << pp::StatusName(size.status) << " at "
              << (error.field ? error.field : "?") << ")\n";
    std::exit(1);
  }
  frames.push_back(nlohmann::ordered_json{{"name", name},
                                          {"type", M::kInfo.name},
                                          {"seq", seq},
                                          {"flags", flags},
                                          {"hex", palpa::host::ToHex(frame, size.value)},
                                          {"fields", palpa::host::MessageToJson(m)}});
}

template <size_t N>
std::array<char, N> Text(const char* s) {
  std::array<char, N> t{};
  for (size_t i = 0; i < N && s[i] != '\0'; ++i) t[i] = s[i];
  return t;
}

void Bootstrap() {
  const uint8_t board = pp::flags::kFromBoard;
  const uint8_t reliable = pp::flags::kReliable;
  Add("hello", pp::Hello{0x12345678, 0}, 0, 0);
  Add("hello_seq_near_wrap", pp::Hello{0xDEADBEEF, 250}, 0, 0);
  pp::HelloReply r;
  r.host_nonce = 0x12345678;
  r.boot_nonce = 0xA5A5F00D;
  r.board_kind = pp::BoardKind::kSim;
  r.board_id = 42;
  r.firmware_major = 0;
  r.firmware_minor = 1;
  r.firmware_patch = 0;
  r.catalog_hash = 0x0BADCAFE;
  r.reset_cause = pp::ResetCause::kPowerOn;
  r.config_is_default = true;
  r.plant_simulated = true;
  r.time_scale = 10.0f;
  r.rx_buffer_bytes = 1024;
  r.active_slot = 0;
  r.rollback_counter = 3;
  r.host_timeout_us = 100000;
  r.fault_bitmap = 0;
  r.config_name = Text<24>("thesis-5finger");
  r.line_count = 7;
  for (uint8_t i = 0; i < 7; ++i) {
    const bool vacuum = i >= 5;
    const bool bias = i == 3 || i == 4;
    r.lines[i] = pp::LineSummary{
        vacuum ? pp::LineKind::kVacuum : (bias ? pp::LineKind::kBias : pp::LineKind::kPressure),
        true, vacuum ? -100000 : 0, vacuum ? 0 : (bias ? 20000 : 100000)};
  }
  r.finger_count = 5;
  for (uint8_t f = 0; f < 5; ++f) {
    const bool jamming = f >= 3;
    r.fingers[f] = pp::FingerSummary{
        jamming ? pp::FingerKind::kJamming : pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, f,
        jamming ? static_cast<uint8_t>(f + 2) : pp::kNoLine};
  }
  Add("hello_reply_thesis_5finger", r, 0, board);
  Add("ack", pp::Ack{0xA5A5F00D, 0x30}, 7, board);
  Add("nack_out_of_range", pp::Nack{0xA5A5F00D, 0x21, pp::Status::kOutOfRange, 2}, 0, board);
  Add("nack_seq_gap", pp::Nack{0xA5A5F00D, 0x30, pp::Status::kSeqGap, 9}, 11, board);
  Add("nack_no_session", pp::Nack{0, 0x20, pp::Status::kNoSession, 0}, 0, board);
  // A second host's Hello while a session is open: busy, with the board's host-silence timeout.
  Add("nack_hello_busy", pp::Nack{0xA5A5F00D, 0x01, pp::Status::kBusy, 100000}, 0, board);
  Add("estop", pp::EStop{}, 0, 0);
  Add("update_enter", pp::UpdateEnter{1, 65536}, 0, reliable);
  Add("update_erase", pp::UpdateErase{1, 0, 65536}, 1, reliable);
  pp::UpdateWrite zeros{1, 4096, 240, {}};
  Add("update_write_all_zero_chunk", zeros, 2, reliable);
  pp::UpdateWrite small{1, 0, 4, {}};
  small.data[0] = 0x00;
  small.data[1] = 0x20;
  small.data[2] = 0x00;
  small.data[3] = 0x20;
  Add("update_write_small", small, 3, reliable);
  Add("update_query", pp::UpdateQuery{1}, 4, reliable);
  pp::UpdateStatus st{0xA5A5F00D, 1, 65536, {}, true};
  for (size_t i = 0; i < st.written_sha256.size(); ++i)
    st.written_sha256[i] = static_cast<uint8_t>(i);
  Add("update_status", st, 4, board);
  pp::UpdateActivate act{1, 65536, {}};
  act.image_sha256.fill(0xFF);
  Add("update_activate_hash_all_ff", act, 5, reliable);
  Add("update_reboot", pp::UpdateReboot{}, 6, reliable);
  Add("update_confirm", pp::UpdateConfirm{1}, 0, reliable);
  Add("slots_query", pp::SlotsQuery{}, 1, reliable);
  pp::SlotsReport slots{0xA5A5F00D, 1, 2, {}};
  slots.slots[0] =
      pp::SlotInfo{pp::SlotState::kConfirmed, pp::BoardKind::kMps2An386, 0, 1, 0, 3, 61440};
  slots.slots[1] =
      pp::SlotInfo{pp::SlotState::kTrial, pp::BoardKind::kMps2An386, 0, 2, 0, 4, 62000};
  Add("slots_report", slots, 1, board);
}

void Streams() {
  // Every stream frame names its session: the nonce of the Hello that opened it.
  Add("heartbeat", pp::Heartbeat{0x12345678, 1}, 0, 0);
  Add("heartbeat_generation_wrap", pp::Heartbeat{0x12345678, 0xFFFFFFFF}, 0, 0);
  pp::SetLineSetpoints sp{};
  sp.session = 0x12345678;
  sp.generation = 17;
  sp.entry_count = 3;
  sp.entries[0] = {0, 10000};
  sp.entries[1] = {1, 30000};
  sp.entries[2] = {6, -100000};
  Add("set_line_setpoints", sp, 0, 0);
  pp::SetLineSetpoints full{};
  full.session = 0xDEADBEEF;
  full.generation = 18;
  full.entry_count = 8;
  for (uint8_t i = 0; i < 8; ++i) full.entries[i] = {i, 100000};
  Add("set_line_setpoints_all_lines_max", full, 0, 0);
  pp::SetFingerTargets t{};
  t.session = 0x12345678;
  t.generation = 5;
  t.entry_count = 2;
  t.entries[0] = {0, pp::OutputUnit::kDeformationMicrometre, 1200};
  t.entries[1] = {3, pp::OutputUnit::kStiffnessMilliNewtonPerMm, 900};
  Add("set_finger_targets", t, 0, 0);
  Add("set_finger_mode_raw", pp::SetFingerMode{4, pp::FingerMode::kRaw}, 12, pp::flags::kReliable);
  Add("close", pp::Close{0x12345678}, 0, 0);
  Add("release", pp::Release{0x12345678}, 0, 0);
  Add("ack_close", pp::Ack{0xA5A5F00D, 0x24}, 0, pp::flags::kFromBoard);
}

void Configuration() {
  const uint8_t reliable = pp::flags::kReliable;
  pp::ConfigureLine line{};
  line.line = 0;
  line.kind = pp::LineKind::kPressure;
  line.dac_bits = 12;
  line.dac_signal = pp::SignalRange::kVolt0To10;
  line.command_min_pa = 0;
  line.command_max_pa = 100000;
  line.limit_min_pa = 0;
  line.limit_max_pa = 100000;
  line.safe_pa = 0;
  line.slew_pa_per_s = 500000;
  line.regulator_min_pa = 1000;
  line.sensor = pp::SensorKind::kAnalog;
  line.adc_bits = 14;
  line.sensor_min_pa = 0;
  line.sensor_max_pa = 103421;
  line.sensor_counts_min = 1638;
  line.sensor_counts_max = 14745;
  line.trim_kp = 0.25f;
  line.trim_ki_per_s = 2.0f;
  line.trim_authority_pa = 5000;
  line.trim_dead_band_pa = 100;
  line.model_tau_us = 20000;
  line.model_dead_time_us = 5000;
  line.correction_count = 3;
  line.correction[0] = {0, 0, 0};
  line.correction[1] = {50000, 49500, 50500};
  line.correction[2] = {100000, 99000, 100000};
  Add("configure_line_pressure", line, 20, reliable);
  pp::ConfigureLine zero{};  // every numeric field 0: a body mostly of 0x00
  zero.dac_bits = 8;
  zero.adc_bits = 8;
  Add("configure_line_mostly_zero", zero, 21, reliable);
  pp::ConfigureFinger finger{};
  finger.finger = 3;
  finger.kind = pp::FingerKind::kJamming;
  finger.line_a = 3;
  finger.line_b = 5;
  finger.bias_pa = 20000;
  finger.actuator_serial = Text<12>("JAM-0004");
  finger.inverse_count = 3;
  finger.inverse[0] = {700, 0};
  finger.inverse[1] = {1000, -50000};
  finger.inverse[2] = {1300, -100000};
  finger.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  finger.param_count = 5;
  const float params[] = {1.0f, 0.5f, 0.25f, 0.0f, 5000.0f};
  for (int i = 0; i < 5; ++i) finger.params[i] = params[i];
  Add("configure_finger_jamming", finger, 22, reliable);
  pp::ConfigureBoard board{};
  board.config_name = Text<24>("thesis-pneumatic-3");
  Add("configure_board", board, 23, reliable);
  Add("staged_begin", pp::StagedBegin{600}, 24, reliable);
  pp::StagedPart part{0, pp::kMaxStagedChunk, {}};
  part.data.fill(0xFF);
  Add("staged_part_max_packet_all_ff", part, 25, reliable);
  Add("staged_commit", pp::StagedCommit{600, 0xCBF43926}, 26, reliable);
  Add("get_config_line", pp::GetConfig{pp::ConfigSection::kLine, 2, 0}, 27, reliable);
  pp::ConfigReport report{0xA5A5F00D, pp::ConfigSection::kLine, 2, 0x11223344, 120, 0, 4, {}};
  report.data[0] = 2;
  report.data[1] = 0;
  report.data[2] = 12;
  report.data[3] = 1;
  Add("config_report", report, 27, pp::flags::kFromBoard);
  Add("save_config", pp::SaveConfig{}, 28, reliable);
  Add("factory_reset", pp::FactoryReset{}, 29, reliable);
  Add("clear_fault_all", pp::ClearFault{}, 30, reliable);
  Add("seq_wraps_to_zero", pp::ClearFault{0x1}, 255, reliable | pp::flags::kRetransmit);
}

void Reports() {
  const uint8_t board = pp::flags::kFromBoard;
  pp::Telemetry t{};
  t.boot_nonce = 0xA5A5F00D;
  t.first_sample_us = 123456789012ull;
  t.sample_interval_us = 1000;
  t.tick_count = 2;
  t.line_count = 8;
  t.setpoint_generation = 17;
  t.target_generation = 5;
  t.fault_bitmap = 0;
  t.dropped_frames = 0;
  t.sample_count = 16;
  for (uint8_t i = 0; i < 16; ++i) {
    t.samples[i] =
        pp::LineSample{10000 * (i % 8), 10000 * (i % 8) - 37, static_cast<uint16_t>(409 * (i % 8)),
                       static_cast<uint8_t>(i % 8 == 7 ? pp::line_status::kOpenLoop : 0)};
  }
  Add("telemetry_8_lines_2_ticks", t, 3, board);
  pp::Telemetry faulted{};
  faulted.boot_nonce = 0xA5A5F00D;
  faulted.first_sample_us = 5000;
  faulted.sample_interval_us = 1000;
  faulted.tick_count = 1;
  faulted.line_count = 1;
  faulted.fault_bitmap = 1;
  faulted.sample_count = 1;
  faulted.samples[0] = pp::LineSample{0, 0, 0, pp::line_status::kSafe};
  Add("telemetry_faulted", faulted, 4, board | pp::flags::kFaulted);
  Add("get_loop_stats", pp::GetLoopStats{}, 31, pp::flags::kReliable);
  Add("loop_stats", pp::LoopStats{0xA5A5F00D, 600000, 1000, 12, 180, 95, 0, 3, 120000, 2}, 31,
      board);
  Add("get_diagnostics", pp::GetDiagnostics{}, 32, pp::flags::kReliable);
  pp::Diagnostics d{};
  d.boot_nonce = 0xA5A5F00D;
  d.reset_cause = pp::ResetCause::kWatchdog;
  d.boot_count = 9;
  d.fault_bitmap = 0x11;
  d.active_conditions = 0x10;
  d.uptime_us = 3600000000ull;
  d.shaping_fallback_lines = 0x21;
  d.history_count = 2;
  d.history[0] = {100, 4, 0};
  d.history[1] = {2500000, 0, 100000};
  Add("diagnostics", d, 32, board | pp::flags::kFaulted);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: palpa_golden_gen OUTPUT.json\n";
    return 2;
  }
  Bootstrap();
  Streams();
  Configuration();
  Reports();
  std::ofstream out(argv[1]);
  out << frames.dump(1) << "\n";
  return out.good() ? 0 : 1;
}
