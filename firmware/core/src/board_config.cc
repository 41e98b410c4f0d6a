// Validation of lines, fingers and whole configurations against the hard ceilings and each other.
#include "palpa/core/board_config.h"

#include "palpa/core/ceilings.h"
#include "palpa/core/compensator.h"
#include "palpa/core/curve.h"
#include "palpa/protocol/messages_report.h"

namespace palpa::core {
namespace {

using protocol::ConfigSection;
using protocol::FingerKind;
using protocol::LineKind;

constexpr float kTwoPi = 6.2831853f;

Status Fail(ConfigError* error, ConfigSection section, uint8_t index, const char* reason,
            Status status = Status::kOutOfRange) {
  if (error != nullptr) *error = ConfigError{section, index, reason};
  return status;
}

bool Within(int32_t value, int32_t lo, int32_t hi) { return value >= lo && value <= hi; }

int32_t Abs(int32_t v) { return v < 0 ? -v : v; }

Status ValidateCorrection(const protocol::ConfigureLine& line, ConfigError* error) {
  const uint8_t n = line.correction_count;
  if (n == 0) return Status::kOk;
  if (n == 1)
    return Fail(error, ConfigSection::kLine, line.line, "correction needs >= 2 points",
                Status::kBadValue);
  int32_t command[protocol::kMaxCorrectionPoints], rising[protocol::kMaxCorrectionPoints],
      falling[protocol::kMaxCorrectionPoints];
  for (uint8_t i = 0; i < n; ++i) {
    command[i] = line.correction[i].command_pa;
    rising[i] = line.correction[i].rising_pa;
    falling[i] = line.correction[i].falling_pa;
  }
  const int direction = Direction(command, n, true);
  const int rising_direction = Direction(rising, n, true);
  const int falling_direction = Direction(falling, n, true);
  if (direction == 2 || rising_direction != direction || falling_direction != direction) {
    return Fail(error, ConfigSection::kLine, line.line, "correction not strictly monotone",
                Status::kBadValue);
  }
  return Status::kOk;
}

}  // namespace

Status ValidateLine(const protocol::ConfigureLine& line, ConfigError* error) {
  const uint8_t i = line.line;
  const Ceiling ceiling = CeilingFor(line.kind);
  if (!Within(line.limit_min_pa, ceiling.min_pa, ceiling.max_pa) ||
      !Within(line.limit_max_pa, ceiling.min_pa, ceiling.max_pa)) {
    return Fail(error, ConfigSection::kLine, i, "limits beyond the hard ceiling");
  }
  if (line.limit_min_pa > line.limit_max_pa)
    return Fail(error, ConfigSection::kLine, i, "limit_min > limit_max");
  if (!Within(line.safe_pa, line.limit_min_pa, line.limit_max_pa)) {
    return Fail(error, ConfigSection::kLine, i, "safe value outside the limits");
  }
  // Below the regulator's minimum the line commands 0 Pa (line_pipeline.cc): limits that leave
  // 0 Pa out must not reach below that minimum, or the line would command outside them.
  const bool zero_within = line.limit_min_pa <= 0 && line.limit_max_pa >= 0;
  const int32_t nearest_zero = line.limit_min_pa > 0 ? line.limit_min_pa : -line.limit_max_pa;
  if (!zero_within && nearest_zero < line.regulator_min_pa) {
    return Fail(error, ConfigSection::kLine, i,
                "limits leave 0 Pa out but reach below the regulator's minimum, where the line "
                "commands 0 Pa");
  }
  if (line.command_min_pa == line.command_max_pa) {
    return Fail(error, ConfigSection::kLine, i, "command range is empty", Status::kBadValue);
  }
  const Ceiling command = CommandRange(line.command_min_pa, line.command_max_pa);
  if (!Within(line.limit_min_pa, command.min_pa, command.max_pa) ||
      !Within(line.limit_max_pa, command.min_pa, command.max_pa)) {
    return Fail(error, ConfigSection::kLine, i, "limits outside the regulator's command range");
  }
  if (line.sensor == protocol::SensorKind::kAnalog) {
    const uint32_t adc_max = (1u << line.adc_bits) - 1u;
    if (line.sensor_counts_min >= line.sensor_counts_max || line.sensor_counts_max > adc_max) {
      return Fail(error, ConfigSection::kLine, i, "sensor counts not within the ADC",
                  Status::kBadValue);
    }
    if (line.sensor_min_pa >= line.sensor_max_pa) {
      return Fail(error, ConfigSection::kLine, i, "sensor range is empty", Status::kBadValue);
    }
  }
  // The pressure trim is a cascade around the regulator's own loop: crossover at most 1 Hz.
  if (line.trim_kp > 1.0f || line.trim_ki_per_s > kTwoPi) {
    return Fail(error, ConfigSection::kLine, i, "trim gains above the 1 Hz crossover");
  }
  const int32_t full_scale = Abs(line.command_max_pa - line.command_min_pa);
  if (line.trim_authority_pa > full_scale / 10) {
    return Fail(error, ConfigSection::kLine, i, "trim authority above 10 % F.S.");
  }
  if (line.model_dead_time_us > 31000) {
    return Fail(error, ConfigSection::kLine, i, "regulator dead time above 31 ms");
  }
  return ValidateCorrection(line, error);
}

Status ValidateFinger(const protocol::ConfigureFinger& finger, const BoardConfig& config,
                      ConfigError* error) {
  const uint8_t f = finger.finger;
  const ConfigSection s = ConfigSection::kFinger;
  if (finger.line_a >= config.line_count) return Fail(error, s, f, "line_a is not configured");
  const auto& a = config.lines[finger.line_a];
  const protocol::ConfigureLine* driven = &a;
  if (finger.kind == FingerKind::kPneumatic) {
    if (a.kind != LineKind::kPressure)
      return Fail(error, s, f, "pneumatic finger needs a pressure line", Status::kBadValue);
    if (finger.line_b != protocol::kNoLine)
      return Fail(error, s, f, "pneumatic finger has one line", Status::kBadValue);
    if (finger.bias_pa != 0)
      return Fail(error, s, f, "pneumatic finger has no bias", Status::kBadValue);
  } else {
    if (a.kind != LineKind::kBias)
      return Fail(error, s, f, "jamming finger needs a bias line as line_a", Status::kBadValue);
    if (finger.line_b >= config.line_count ||
        config.lines[finger.line_b].kind != LineKind::kVacuum) {
      return Fail(error, s, f, "jamming finger needs a vacuum line as line_b", Status::kBadValue);
    }
    if (!Within(finger.bias_pa, a.limit_min_pa, a.limit_max_pa))
      return Fail(error, s, f, "bias outside the bias line's limits");
    driven = &config.lines[finger.line_b];
  }
  const uint8_t n = finger.inverse_count;
  if (n < 2) return Fail(error, s, f, "static inverse needs >= 2 points", Status::kBadValue);
  int32_t output[protocol::kMaxInversePoints], setpoint[protocol::kMaxInversePoints];
  for (uint8_t i = 0; i < n; ++i) {
    output[i] = finger.inverse[i].output;
    setpoint[i] = finger.inverse[i].setpoint_pa;
    if (!Within(setpoint[i], driven->limit_min_pa, driven->limit_max_pa)) {
      return Fail(error, s, f, "static inverse outside the line's limits");
    }
  }
  if (Direction(output, n, true) != 1)
    return Fail(error, s, f, "inverse outputs not strictly increasing", Status::kBadValue);
  if (Direction(setpoint, n, false) == 2)
    return Fail(error, s, f, "inverse setpoints not monotone", Status::kBadValue);
  if (const char* why = CompensatorParamsError(finger))
    return Fail(error, s, f, why, Status::kBadValue);
  return Status::kOk;
}

Status ValidateConfig(const BoardConfig& config, ConfigError* error) {
  if (config.line_count > protocol::kMaxLines || config.finger_count > protocol::kMaxFingers) {
    return Fail(error, ConfigSection::kBoard, 0, "too many lines or fingers");
  }
  const uint8_t batch_limit = static_cast<uint8_t>(protocol::kMaxTelemetrySamples /
                                                   (config.line_count > 0 ? config.line_count : 1));
  if (config.board.telemetry_batch > batch_limit) {
    return Fail(error, ConfigSection::kBoard, 0, "telemetry batch does not fit one frame");
  }
  for (uint8_t i = 0; i < config.line_count; ++i) {
    if (config.lines[i].line != i)
      return Fail(error, ConfigSection::kLine, i, "line index out of order", Status::kBadValue);
    const Status s = ValidateLine(config.lines[i], error);
    if (s != Status::kOk) return s;
  }
  uint8_t owner[protocol::kMaxLines];
  for (uint8_t& o : owner) o = protocol::kNoLine;
  for (uint8_t f = 0; f < config.finger_count; ++f) {
    const auto& finger = config.fingers[f];
    if (finger.finger != f)
      return Fail(error, ConfigSection::kFinger, f, "finger index out of order", Status::kBadValue);
    const Status s = ValidateFinger(finger, config, error);
    if (s != Status::kOk) return s;
    for (uint8_t line : {finger.line_a, finger.line_b}) {
      if (line == protocol::kNoLine) continue;
      if (owner[line] != protocol::kNoLine)
        return Fail(error, ConfigSection::kFinger, f, "line already used by another finger",
                    Status::kBadValue);
      owner[line] = f;
    }
  }
  return Status::kOk;
}

uint8_t FingerOfLine(const BoardConfig& config, uint8_t line) {
  for (uint8_t f = 0; f < config.finger_count; ++f) {
    if (config.fingers[f].line_a == line || config.fingers[f].line_b == line) return f;
  }
  return protocol::kNoLine;
}

}  // namespace palpa::core
