// The device API: one palpa board, its fingers in people's terms, telemetry and recording.
// Errors are values (status + message); nothing throws across this API.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "palpa/core/board_config.h"
#include "palpa/host/board_curves.h"
#include "palpa/host/link.h"
#include "palpa/host/outcome.h"
#include "palpa/host/stiffness_map.h"

namespace palpa::hal::linux_files {
class AtomicFile;
}

namespace palpa::host {

/// A board's whole configuration (board, lines, fingers) as the host holds it: the firmware's own
/// type, so the host validates and encodes it exactly as the board will.
using BoardConfig = core::BoardConfig;

struct DeviceOptions {
  LinkOptions link{};
  LevelTables levels = LevelTables::Shipped();
  RangePolicy range_policy = RangePolicy::kRefuse;
  /// Where calibration files are looked up by each finger's actuator serial when the device
  /// opens; empty: DefaultCalibrationDir(). Set use_calibrations = false for nominal curves.
  std::string calibration_dir;
  bool use_calibrations = true;
  /// A finger whose calibration file is there but cannot be used (invalid, not a regular file,
  /// for another actuator or finger kind) falls back to the nominal curves, and every request
  /// for it says why in its notes; true makes such a request an error instead (kBadValue,
  /// nothing sent). A finger with no file is never an error.
  bool invalid_calibration_is_error = false;
  /// How messages and notes number fingers and lines: from 0, as this API, the C ABI and Python
  /// do, or from 1, as the command line does — an error names a finger as its caller numbered it.
  uint8_t number_from = 0;
};

/// How a recording lays out its samples: a row per sample with a column per line and per finger
/// (wide), or a row per line per sample (long).
enum class RecordLayout { kWide, kLong };

struct FingerRequest {
  uint8_t finger = 0;  ///< 0-based, as on the wire
  Request request;
};

/// What Set made of one request: the target the board follows, or the raw setpoints it holds.
struct Applied {
  uint8_t finger = 0;
  Request request;
  bool raw = false;
  double target = 0;        ///< target mode: in the finger's unit (0: off, released)
  const char* unit = "";    ///< "mm" (pneumatic) or "N/mm" (jamming)
  bool from_table = false;  ///< a level: its table's pressure or vacuum, in table_kpa
  double table_kpa = 0;
  uint8_t line_a = 0, line_b = protocol::kNoLine;  ///< the finger's lines (0-based)
  int32_t line_a_pa = 0, line_b_pa = 0;            ///< raw mode: their setpoints
  std::string map;  ///< the curves the request went through, and any clamping
};

class Device {
 public:
  /// Opens a device URI (see OpenTransport) and a session with it; a sim: device with
  /// `sim_truth_address` non-null streams its truth side channel too, and says where there.
  static Result<std::unique_ptr<Device>> Open(const std::string& uri, DeviceOptions options,
                                              std::string* sim_truth_address = nullptr);
  /// Opens a session over a transport the caller made (tests, fault injection).
  static Result<std::unique_ptr<Device>> Attach(std::unique_ptr<Transport> transport,
                                                DeviceOptions options);
  /// Closes the session (see Close).
  ~Device();

  pp::HelloReply info() const { return link_->board(); }
  /// "finger 3", "line 2": numbered as DeviceOptions::number_from says.
  std::string FingerName(uint8_t finger) const;
  std::string LineName(uint8_t line) const;
  Link& link() { return *link_; }

  /// Sets fingers; each request is mapped through the level tables and the finger's curves, the
  /// finger is switched to target or raw mode as needed, and (wait=true) the call returns once
  /// telemetry shows the board applied it or the board refused it.
  /// `applied` (optional) receives what each request became, in the order given.
  Outcome Set(const std::vector<FingerRequest>& requests, bool wait = true,
              std::vector<Applied>* applied = nullptr);
  /// Raw line setpoints in kPa; the lines' fingers go to raw mode.
  Outcome SetLines(const std::vector<std::pair<uint8_t, double>>& kpa, bool wait = true);
  Outcome EStop();
  Outcome ClearFault(uint32_t mask = 0xFFFFFFFFu);
  /// Ends the session: every output safe at once, no fault latched, the board free for another
  /// host (the destructor does it too). Recording stops. Later calls fail with no_session.
  Outcome Close();
  /// Every output safe at once, no fault latched; the session stays open and a later Set
  /// actuates again.
  Outcome Release();

  Outcome ConfigureLine(const pp::ConfigureLine& line);
  /// Sent staged when it does not fit one packet (large compensators).
  Outcome ConfigureFinger(const pp::ConfigureFinger& finger);
  Outcome ConfigureBoard(const pp::ConfigureBoard& board);
  /// Configure* records (each a 16-bit length, the type, the body: core::EncodeConfigBlob's
  /// format) uploaded staged; the board validates them together and applies all or none.
  Outcome ConfigureStaged(const uint8_t* records, size_t size);
  Outcome SaveConfig();
  Outcome FactoryReset();
  Result<pp::ConfigureLine> ReadLine(uint8_t line);
  Result<pp::ConfigureFinger> ReadFinger(uint8_t finger);
  Result<pp::ConfigureBoard> ReadBoard();
  /// The board's whole live configuration (board, every line, every finger), read section by
  /// section; ConfigToJson (config_json.h) gives it as palpa config show prints it.
  Result<BoardConfig> ReadConfig();
  /// `config` checked with the firmware's own validation (kOutOfRange, naming the section) and
  /// encoded as the staged upload's records (kOverflow when they do not fit the board's staging
  /// buffer): what ApplyConfig sends, found wrong before anything is sent.
  Outcome EncodeConfig(const BoardConfig& config, std::vector<uint8_t>* records) const;
  /// EncodeConfig, then ConfigureStaged: the board validates the whole configuration and applies
  /// all or none of it (live, not saved: SaveConfig keeps it across resets).
  Outcome ApplyConfig(const BoardConfig& config);
  Result<pp::Diagnostics> Diagnostics();
  Result<pp::LoopStats> LoopStats();

  int Subscribe(std::function<void(const TelemetryFrame&)> callback) {
    return link_->Subscribe(std::move(callback));
  }
  void Unsubscribe(int id) { link_->Unsubscribe(id); }

  /// Records telemetry to a CSV file whose first line is a JSON header (board, configuration,
  /// layout, units, numbering, clock); each row has the UTC time and the board time of its sample,
  /// status and faults by name, and (wide) each finger's output estimated through its curve.
  /// Written whole or not at all (file_write.h): to a temporary beside PATH, put in its place by
  /// StopRecording, so a file at PATH is always complete.
  Outcome StartRecording(const std::string& path, RecordLayout layout = RecordLayout::kWide);
  Outcome StopRecording();

  /// The curves used for finger f (nominal until a calibration is attached).
  FingerCurves& curves(uint8_t finger) {
    AttachCalibrations();
    return curves_[finger];
  }
  /// The level tables requests are mapped through (DeviceOptions::levels).
  const LevelTables& levels() const { return options_.levels; }
  /// What opening found for each finger: which calibration it uses, or why it uses none.
  /// Looked up on first use (Set, curves, this), not on opening: an E-stop never waits for it.
  const std::vector<std::string>& calibration_notes() {
    AttachCalibrations();
    return calibration_notes_;
  }

  /// Calibration files that disagree with the static inverse their finger's board holds by more
  /// than their fit residual (board_curves.h): requests follow the board's curve, and this says
  /// which file, which finger and by how much. Looked up as calibration_notes() is.
  const std::vector<CurveWarning>& curve_warnings() {
    AttachCalibrations();
    return curve_warnings_;
  }

  /// Uploads a calibration to finger f in one staged, all-or-nothing change: static inverse,
  /// compensator and its parameters, the recommended bias (jamming), the regulator corrections of
  /// the finger's lines. Refused when the finger's kind or actuator serial differ from the file's.
  /// The finger's curves follow the calibration afterwards.
  Outcome ApplyCalibration(uint8_t finger, const struct CalibrationFile& calibration);

 private:
  explicit Device(std::unique_ptr<Link> link, DeviceOptions options);
  Outcome EnsureMode(uint8_t finger, pp::FingerMode mode);
  template <class M>
  Result<M> ReadSection(pp::ConfigSection section, uint8_t index);
  static Outcome FromCommand(const CommandResult& r, const char* what);
  /// A stream the board did not apply: why, in words; for latched faults each one named with
  /// when it latched (read from the board's fault history) and what to do.
  Outcome StreamRefused(Status s, uint32_t detail, const char* what,
                        std::vector<std::string> notes);
  /// "faulted: <faults described>; clear them ..." for the faults in `bitmap`.
  std::string FaultText(uint32_t bitmap, bool persist);

  std::unique_ptr<Link> link_;
  DeviceOptions options_;
  std::vector<pp::FingerMode> modes_;
  std::vector<FingerCurves> curves_;
  std::vector<std::string> calibration_notes_;
  /// Per finger: why its calibration file could not be used (empty: used, or there is none).
  std::vector<std::string> calibration_problems_;
  std::vector<CurveWarning> curve_warnings_;
  bool calibrations_attached_ = false;
  void AttachCalibrations();  ///< once per device
  /// Finger f's curve with a calibration file beside what its board holds (board_curves.h).
  void AttachCalibration(uint8_t f, const pp::ConfigureFinger& board,
                         const struct CalibrationFile& file, const std::string& path);
  std::string BoardCurveName(uint8_t finger, const pp::ConfigureFinger& f) const;
  // Recording.
  std::mutex record_mutex_;
  std::unique_ptr<hal::linux_files::AtomicFile> record_;  ///< null when not recording
  std::string record_path_;
  int record_subscription_ = 0;
  RecordLayout record_layout_ = RecordLayout::kWide;
  std::vector<FingerCurves> record_curves_;
  double record_wall_minus_steady_s_ = 0;  ///< maps the link's host (steady) time to UTC
};

}  // namespace palpa::host
