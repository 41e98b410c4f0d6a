// A study's methods ("study."): the experimenter starts a participant's session (the library's
// runner, its journal and provenance, on a thread of its own), the participant's page answers
// each trial and may stop it, and two channels tell each view only what it should know.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "palpa/host/study_file.h"
#include "palpa/host/study_records.h"
#include "palpa/host/study_runner.h"
#include "palpa/serve/board_methods.h"

namespace palpa::serve {

/// A study file the operator named on the command line (palpa serve --study FILE): read at
/// start, offered to pages by its name. A page itself never names a file on the server.
struct ServerStudy {
  std::string name;
  host::Study study;
};

struct StudyServeOptions {
  /// Where sessions go, each in DIR/STUDY/PARTICIPANT (palpa serve --study-dir); empty: none
  /// can start.
  std::string study_dir;
  std::vector<ServerStudy> server_studies;
  /// The board as the provenance names it (the device URI).
  std::string board;
  /// A simulated board's seed and unit (from its link's description), for the provenance.
  std::optional<host::SimProvenance> sim;
  std::string calibration_dir;
  bool use_calibrations = true;
  /// Called on the runner's thread at each trigger event, before the event is published: palpa
  /// serve --trigger-gpio pulses its line there. Empty: the events are notifications only.
  std::function<void(const host::TriggerEvent&)> on_trigger;
  /// The trigger line as the operator named it (CHIP:LINE), for study.list; empty: none.
  std::string trigger_gpio;
};

/// study.list, study.start, study.watch, study.answer, study.next and study.stop; channels
/// "study.participant" (notify_study_participant) and "study.experimenter" (notify_study).
MethodGroup StudyMethods(StudyServeOptions options);

}  // namespace palpa::serve
