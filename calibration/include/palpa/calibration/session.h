// A calibration session as an application runs one: a finger on a rig, its journal to resume
// from, the run, and the calibration file, raw readings and report written to a directory.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/calibration/calibration_protocol.h"
#include "palpa/calibration/rig.h"
#include "palpa/host/device.h"

namespace palpa::calibration {

struct SessionOptions {
  uint8_t finger = 0;  ///< from 0, as on the wire
  ProtocolOptions protocol;
  /// Where SERIAL.json, SERIAL.csv, SERIAL.html and the journal go; empty: nowhere (the run's
  /// results stay in memory, and a stopped run cannot resume).
  std::string out_dir;
  bool resume = false;  ///< continue the journal OUT/SERIAL.journal.json
  std::string
      previous;  ///< the actuator's last calibration; empty: OUT/SERIAL.json if there is one
  /// A compensator that cannot be fitted leaves the static inverse alone instead of failing.
  bool allow_fallback = false;
  std::optional<std::string> date;                 ///< UTC ISO 8601; empty: now
  std::optional<host::SimulatedPlant> simulation;  ///< on palpa-sim's rig: which plant
  /// Told why when the journal could not be saved after a step (the run goes on, but a stopped
  /// run could not resume).
  std::function<void(const std::string& why)> journal_not_saved;
};

/// One finger's calibration, in phases an application (or palpa calibrate) runs in order:
/// OpenOutput, Resume (with options.resume), LoadPrevious, Run, Write. Calibrate runs them all.
/// Nothing is written before Run has a result, except the journal as each step finishes.
class Session {
 public:
  /// `rig` is the finger's rig; `serial` the finger's actuator (ReadActuatorSerial), `board_id`
  /// the board's, both recorded in the file.
  Session(const Rig& rig, std::string serial, uint32_t board_id, bool jamming,
          SessionOptions options);

  /// The hysteresis sweep this finger gets, and what it can fit (said before the run).
  SweepCapacity Sweep() const;
  /// kInvalidArgument, naming why, when the compensator asked for cannot be fitted to the sweep
  /// and options.allow_fallback is off (checked before anything moves).
  host::Outcome CheckSweep() const;

  /// Makes the output directory (another session may have made it meanwhile); kIoError.
  host::Outcome OpenOutput();
  /// Reads the journal back: kNotFound when there is none, kBadValue when it is damaged.
  host::Outcome Resume();
  /// The actuator's last calibration, for the detector that notices it changed: kBadValue when
  /// it cannot be read, kInvalidArgument when it calibrates another actuator.
  host::Outcome LoadPrevious();
  /// The protocol on the rig. When a step stopped it (stopped(): the stage retracted, the board
  /// vented, the journal kept) the rig's status says why: kOutOfRange for a safety limit (force,
  /// depth, travel), kUnavailable for a device that no longer answers, kFaulted for a board
  /// fault. kBadValue when the compensator could not be fitted and options.allow_fallback is off
  /// (the journal kept, nothing written).
  host::Outcome Run(const std::function<void(const Progress&)>& progress);
  /// The last Run was stopped on the rig (not a fit that failed after it).
  bool stopped() const { return stopped_; }
  /// The calibration file, raw readings and report, each whole; the journal then goes. kIoError.
  host::Outcome Write();
  /// All phases in order; the first that fails ends it.
  host::Outcome Calibrate(const std::function<void(const Progress&)>& progress);

  const std::string& serial() const { return serial_; }
  bool jamming() const { return jamming_; }
  const CalibrationRun& result() const { return run_; }
  /// OUT/SERIAL: the files are BASE.json, BASE.csv, BASE.html and BASE.journal.json.
  std::string base() const { return options_.out_dir + "/" + serial_; }
  std::vector<std::string> files() const;
  /// What was calibrated and how well, as palpa calibrate --json prints it (the finger numbered
  /// from `number_from`).
  nlohmann::ordered_json Summary(bool applied, int number_from) const;

 private:
  Rig rig_;
  std::string serial_;
  uint32_t board_id_;
  bool jamming_;
  SessionOptions options_;
  Journal journal_;
  std::optional<host::CalibrationFile> previous_;
  CalibrationRun run_;
  bool stopped_ = false;
};

}  // namespace palpa::calibration
