// The recording's CSV: a row per sample with a column per line and per finger (wide), or a row
// per line per sample (long); UTC and board time on every row, status and faults by name.
#include "recording_format.h"

#include <cmath>
#include <cstdio>
#include <ctime>

#include "palpa/host/bit_names.h"
#include "palpa/host/board_json.h"
#include "palpa/host/field_text.h"

namespace palpa::host::recording {

namespace {

/// "mm" → "mm", "N/mm" → "n_per_mm": a unit as a column-name suffix.
std::string UnitColumn(pp::FingerKind kind) {
  return kind == pp::FingerKind::kJamming ? "n_per_mm" : "mm";
}

}  // namespace

nlohmann::ordered_json Header(const pp::HelloReply& b, RecordLayout layout,
                              const std::vector<FingerCurves>& curves) {
  nlohmann::ordered_json header;
  header["format"] = "palpa recording 2";
  header["layout"] = layout == RecordLayout::kWide ? "wide: one row per sample"
                                                   : "long: one row per line per sample";
  header["board"] = {
      {"kind", pp::kBoardKindNames[static_cast<int>(b.board_kind)]},
      {"id", b.board_id},
      {"firmware", std::to_string(b.firmware_major) + "." + std::to_string(b.firmware_minor) + "." +
                       std::to_string(b.firmware_patch)},
      {"catalog_hash", b.catalog_hash},
      {"plant_simulated", b.plant_simulated},
      {"time_scale", b.time_scale}};
  header["configuration"] = FieldText(b.config_name);
  header["numbering"] = "lines and fingers from 1, as palpa info and the command line count them";
  header["lines"] = LinesJson(b);
  header["fingers"] = FingersJson(b, &curves);
  header["units"] = {
      {"utc_time", "UTC, ISO 8601: the host's wall clock when the board took the sample"},
      {"board_time_us", "us, the board's clock since it booted"},
      {"setpoint_pa", "Pa"},
      {"measured_pa", "Pa (0 where a line has no sensor)"},
      {"command_counts", "DAC counts"},
      {"status", "the line's status bits by name, | between them; ok: none set"},
      {"faults", "the latched faults by name, | between them; none: no fault"},
      {"mm",
       "a pneumatic finger's deformation, estimated from its line's pressure through its "
       "curve (static: the hysteresis the board compensates is not in it)"},
      {"n_per_mm", "a jamming finger's stiffness, estimated the same way from its vacuum"}};
  header["clock"] = {{"utc_time",
                      "board time mapped to host time through the least-delayed telemetry frames "
                      "of the last 10 s, then to the wall clock"},
                     {"time_scale", b.time_scale}};
  return header;
}

std::string Columns(const pp::HelloReply& b, RecordLayout layout) {
  if (layout == RecordLayout::kLong) {
    return "utc_time,board_time_us,line,setpoint_pa,measured_pa,command_counts,status,faults";
  }
  std::string columns = "utc_time,board_time_us,faults";
  for (uint8_t i = 0; i < b.line_count; ++i) {
    const std::string line = "line" + std::to_string(i + 1) + "_";
    columns += "," + line + "setpoint_pa," + line + "measured_pa," + line + "command_counts," +
               line + "status";
  }
  for (uint8_t f = 0; f < b.finger_count; ++f)
    columns += ",finger" + std::to_string(f + 1) + "_" + UnitColumn(b.fingers[f].kind);
  return columns;
}

std::string UtcText(double unix_seconds) {
  double whole = std::floor(unix_seconds);
  long micros = std::lround((unix_seconds - whole) * 1e6);
  if (micros >= 1000000) {
    whole += 1;
    micros -= 1000000;
  }
  const std::time_t t = static_cast<std::time_t>(whole);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[40];
  const size_t n = std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(text + n, sizeof(text) - n, ".%06ldZ", micros);
  return text;
}

void AppendRows(std::string& out, const pp::HelloReply& b, RecordLayout layout, double unix_seconds,
                uint64_t board_us, uint32_t faults, const pp::LineSample* lines,
                const std::vector<FingerCurves>& curves) {
  const std::string when = UtcText(unix_seconds) + "," + std::to_string(board_us);
  const std::string fault_names = JoinNames(FaultList(faults), "|", "none");
  char cell[96];
  if (layout == RecordLayout::kLong) {
    for (uint8_t i = 0; i < b.line_count; ++i) {
      std::snprintf(cell, sizeof(cell), ",%u,%d,%d,%u,", i + 1u, lines[i].setpoint_pa,
                    lines[i].measured_pa, lines[i].command_counts);
      out += when + cell + JoinNames(LineStatusList(lines[i].status), "|", "ok") + "," +
             fault_names + "\n";
    }
    return;
  }
  out += when + "," + fault_names;
  for (uint8_t i = 0; i < b.line_count; ++i) {
    std::snprintf(cell, sizeof(cell), ",%d,%d,%u,", lines[i].setpoint_pa, lines[i].measured_pa,
                  lines[i].command_counts);
    out += cell + JoinNames(LineStatusList(lines[i].status), "|", "ok");
  }
  for (double output : EstimateFingerOutputs(b, curves, lines)) {
    std::snprintf(cell, sizeof(cell), ",%.4f", output);
    out += cell;
  }
  out += "\n";
}

}  // namespace palpa::host::recording
