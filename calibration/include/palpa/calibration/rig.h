// A calibration rig: a linear stage, a force sensor and the board, each behind a small interface
// so procedures run the same on lab hardware (Modbus, Net F/T, the host library) and on the
// simulated rig in one process on virtual time.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/host/outcome.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::calibration {

/// Every rig operation says whether it worked and, if not, why — in words and by a code that tells
/// the cases apart: a device that no longer answers (kUnavailable), a safety limit crossed (force,
/// depth, travel: kOutOfRange), a board fault (kFaulted), or the code the board refused with.
using RigStatus = host::Outcome;
using host::Status;

/// Time as the rig lives it: real on hardware, virtual in-process (waiting advances the plant).
class RigTime {
 public:
  virtual ~RigTime() = default;
  virtual double Now() = 0;
  /// Lets `seconds` pass (the board keeps its heartbeat; the stage keeps moving).
  virtual void Wait(double seconds) = 0;
};

class Stage {
 public:
  virtual ~Stage() = default;
  /// Starts a move of the indenter tip to `mm` (height above the rig's zero) at `speed_mm_s`.
  virtual RigStatus MoveTo(double mm, double speed_mm_s) = 0;
  virtual RigStatus Position(double* mm) = 0;
  virtual RigStatus Moving(bool* moving) = 0;
  virtual RigStatus Stop() = 0;
  /// Whether the stage's controller can stop a move by itself on its load cell (a force-limit
  /// stop, as motorised test stands have): where the surface is then does not depend on how late
  /// the host reads the force.
  virtual bool stops_on_force() const { return false; }
  /// Starts a move to `mm` that the controller stops the moment its force reading reaches
  /// `stop_n` (newtons, compressive, after the tare). Only where stops_on_force().
  virtual RigStatus MoveUntilForce(double mm, double speed_mm_s, double stop_n) {
    (void)mm, (void)speed_mm_s, (void)stop_n;
    return RigStatus::Fail(host::Status::kUnsupported, "this stage has no force-limit stop");
  }
};

class ForceSensor {
 public:
  virtual ~ForceSensor() = default;
  virtual RigStatus Read(double* newtons) = 0;  ///< compressive positive, after the tare
  virtual RigStatus Tare() = 0;
};

/// What procedures need of the board: raw drives on a finger's lines, the line's measured
/// pressure, the trim on or off, a bare line for step responses, faults, and venting everything.
class BoardPort {
 public:
  virtual ~BoardPort() = default;
  virtual bool jamming(uint8_t finger) = 0;
  virtual uint8_t driven_line(
      uint8_t finger) = 0;  ///< the pressure (pneumatic) or vacuum (jamming) line
  virtual uint8_t bias_line(uint8_t finger) = 0;  ///< jamming: the bias line (line_a)
  /// Raw mode: `kpa_a` on line_a (pressure or bias), `kpa_b` on line_b (vacuum, ≤ 0).
  virtual RigStatus SetDrive(uint8_t finger, double kpa_a, double kpa_b) = 0;
  virtual RigStatus MeasuredKpa(uint8_t line, double* kpa) = 0;
  /// The largest magnitude the line's limits allow (kPa): the range a correction covers.
  virtual RigStatus LineRangeKpa(uint8_t line, double* kpa) = 0;
  /// Turns the line's PI trim off (feed-forward only) or back to its configured gains.
  virtual RigStatus SetTrim(uint8_t line, bool on) = 0;
  /// A bare line for a step response (`bare`): the trim, the slew limit and step shaping off, so
  /// a new drive reaches the regulator at once and unshaped; or the line's configuration back.
  virtual RigStatus SetBareLine(uint8_t line, bool bare) = 0;
  virtual RigStatus Faults(uint32_t* bitmap) = 0;
  virtual RigStatus VentAll() = 0;
};

/// A line as a step response needs it: no trim, no slew limit, no step shaping.
inline void MakeBare(protocol::ConfigureLine& c) {
  c.trim_kp = c.trim_ki_per_s = 0;
  c.slew_pa_per_s = 0;
  c.chamber_tau_us = 0;
  c.overdrive_pa = 0;
}

/// Limits a run must keep; crossing one aborts it and leaves everything safe.
struct SafetyLimits {
  double max_force_n = 6.0;     ///< stop and retract above this
  double min_position_mm = -4;  ///< deepest the tip may go (depth limit)
  double max_position_mm = 30;  ///< stage soft limit
  double retract_mm = 5;        ///< where a retract goes
};

/// An ATI Nano17 SI-12-0.12 reading: 0.003 N resolution (its quantisation, 0.0009 N RMS) with about
/// half a count of noise on top — the sensor class the thesis calibrated with.
inline constexpr double kNano17NoiseN = 0.0017;

struct Rig {
  Stage& stage;
  ForceSensor& force;
  BoardPort& board;
  RigTime& time;
  SafetyLimits limits{};
  std::string name = "sim";
  double force_noise_n = kNano17NoiseN;  ///< the force sensor's class (noise check)
};

}  // namespace palpa::calibration
