// The participant of a served study session: the runner's callbacks, each waiting on the page.
#pragma once

#include <string>

#include "study_desk.h"

namespace palpa::serve {

class StudyDesk::Participant final : public host::StudyParticipant {
 public:
  explicit Participant(StudyDesk& d) : d_(d) {}

  void Feel(const host::TrialPrompt& t, int finger, host::BoardClock& clock,
            double until_s) override;
  host::Result<host::StudyAnswer> Answer(const host::TrialPrompt& t, host::BoardClock&) override;
  void Refused(const std::string& why) override;
  bool Break(int done, int total) override;

 private:
  StudyDesk& d_;
};

}  // namespace palpa::serve
