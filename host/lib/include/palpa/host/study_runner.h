// The study runner: plays a participant's plan on a board — each trial reset, approached from a
// stated side, set in one frame, timed from the moment the display has settled on the board's
// clock — asks a participant (terminal, browser, simulated) and journals every trial, so that a
// killed session loses at most the trial in progress and resumes in the same order.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/device.h"
#include "palpa/host/study_file.h"
#include "palpa/host/study_plan.h"
#include "palpa/host/study_records.h"

namespace palpa::host {

/// The board's clock as telemetry tells it: the newest sample's time.
class BoardClock {
 public:
  virtual ~BoardClock() = default;
  virtual double now_s() = 0;
  /// Returns once the board's clock has moved on by `seconds` (or the board is gone).
  virtual void Wait(double seconds) = 0;
};

/// What a participant is told about a trial: never the condition.
struct TrialPrompt {
  int index = 0, total = 0;  ///< 0-based index of the trial in the plan, and its length
  std::string block, question;
  StudyMode mode = StudyMode::kSimultaneous;
  BlockKind kind = BlockKind::kDetection;
  bool practice = false;
  int fingers = 0;
  std::vector<int> compared;  ///< staircase: the two fingers (0-based)
};

/// Detection: is there a tumour, and under which fingers (one flag per finger). Staircase: the
/// finger felt stiffer, its flag alone set, tumour true.
struct StudyAnswer {
  bool tumour = false;
  std::vector<bool> fingers;
};

class StudyParticipant {
 public:
  virtual ~StudyParticipant() = default;
  /// Sequential: finger `finger` (0-based) alone is shown; return when the participant moves on
  /// or at `until_s` on the board's clock, whichever is first.
  virtual void Feel(const TrialPrompt& trial, int finger, BoardClock& clock, double until_s) = 0;
  /// Everything has been shown (simultaneous: the display has settled): the answer, or a
  /// cancelled Outcome when the participant stops the session.
  virtual Result<StudyAnswer> Answer(const TrialPrompt& trial, BoardClock& clock) = 0;
  /// The answer was refused (why, in words): Answer is asked again.
  virtual void Refused(const std::string& why) = 0;
  /// A rest before the next trial (the board vented meanwhile); false stops the session.
  virtual bool Break(int done, int total) = 0;
};

/// A timestamped event for other lab equipment: "settled" (the trial clock starts) and
/// "answered", with the trial and the board's time.
struct TriggerEvent {
  std::string kind;
  int trial = 0;
  double board_ms = 0;
};

struct StudyRunOptions {
  std::string out_dir;
  std::string participant;
  bool resume = false;
  /// The board, as the session's provenance says it: the device URI ("sim:thesis-pneumatic-3")
  /// and, on a simulated board, its seed and unit (null otherwise).
  std::string board;
  std::optional<SimProvenance> sim;
  /// Where the device looks up calibration files (as DeviceOptions): the files of the study's
  /// fingers are hashed into the provenance.
  std::string calibration_dir;
  bool use_calibrations = true;
  std::function<void(const TriggerEvent&)> on_trigger;
  std::function<void(const std::string&)> progress;  ///< a line per trial, for the experimenter
  /// The session is claimed (session.json written): a caller that started the run on a thread of
  /// its own learns that the directory and the board were accepted.
  std::function<void()> on_started;
  /// Optional: true once the session is to stop (a participant's stop button). Nothing is set on
  /// the board after it says so, waits on the board's clock end, and the run returns cancelled
  /// with what was journalled kept (a resume continues).
  std::function<bool()> stopped;
};

/// The trial's settle moment from its lines' telemetry (study_settle.cc).
struct SettleLine {
  uint8_t line = 0;
  /// The line's chamber_tau_us: the tube's lag at the board's reference pressure for its kind
  /// (host/chamber_tube.h); 0: none (the outlet alone).
  double tau_s = 0;
  protocol::LineKind kind = protocol::LineKind::kPressure;
};

/// Runs (or with resume continues) the session. Refuses, before anything is set: a study the
/// board cannot play (fingers, kinds, the cap through the fingers' curves, the jamming bias),
/// an output directory holding a session (without resume) or none (with it), a resumed session
/// of another study or participant. Ends with the board released.
Outcome RunStudy(Device& device, const Study& study, StudyParticipant& participant,
                 const StudyRunOptions& options);

/// A participant id, which names the session and its records: 1 to 64 letters, digits, '_', '.'
/// or '-', not starting with '.' or '-'. Invalid argument, in words.
Outcome CheckParticipant(const std::string& id);

/// Checks an answer against the trial: one flag per finger; a tumour marks 1 … fingers − 1
/// fingers, no tumour none; a staircase answer marks one of the two compared fingers.
Outcome CheckAnswer(const TrialPrompt& trial, const StudyAnswer& answer);

/// "n" (no tumour), or finger numbers counted from 1 ("2", "1 2", "1,2"): a detection answer
/// typed at a terminal; a staircase answer is one finger's number. Invalid argument, in words.
Result<StudyAnswer> ParseAnswerText(const TrialPrompt& trial, const std::string& text);

}  // namespace palpa::host
