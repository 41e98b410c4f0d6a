// The participant of a served study session is the page: each callback of the runner waits on the
// API through the desk, and the page is told only the prompt — never a condition, a stimulus or a
// correctness.
#include "study_desk_participant.h"

#include <chrono>

namespace palpa::serve {
namespace {

// File-local: other files of the unity batch alias Json in their own.
using Json = rpc::Json;
using host::Status;

/// What the participant's page may know of a trial: the question and how to answer it.
Json PromptJson(const host::TrialPrompt& t, const char* state) {
  return {{"state", state},
          {"trial", t.index},
          {"question", t.question},
          {"kind", t.kind == host::BlockKind::kStaircase ? "staircase" : "detection"},
          {"mode", t.mode == host::StudyMode::kSequential ? "sequential" : "simultaneous"},
          {"fingers", t.fingers},
          {"compared", t.compared},
          {"practice", t.practice}};
}

}  // namespace

void StudyDesk::Participant::Feel(const host::TrialPrompt& t, int finger, host::BoardClock& clock,
                                  double until_s) {
  std::unique_lock<std::mutex> lock(d_.mutex_);
  d_.waiting_ = Waiting::kFeel;
  d_.prompt_ = t;
  d_.next_ = false;
  Json state = PromptJson(t, "feel");
  state["finger"] = finger;
  d_.PublishParticipant(std::move(state));
  while (!d_.next_ && !d_.stop_) {
    lock.unlock();
    const double now = clock.now_s();
    lock.lock();
    if (now >= until_s) break;
    d_.changed_.wait_for(lock, std::chrono::milliseconds(20));
  }
  d_.waiting_ = Waiting::kNone;
  d_.PublishParticipant({{"state", "wait"}});
}

host::Result<host::StudyAnswer> StudyDesk::Participant::Answer(const host::TrialPrompt& t,
                                                               host::BoardClock&) {
  std::unique_lock<std::mutex> lock(d_.mutex_);
  d_.waiting_ = Waiting::kAnswer;
  d_.prompt_ = t;
  d_.answer_.reset();
  d_.PublishParticipant(PromptJson(t, "answer"));
  d_.changed_.wait(lock, [&] { return d_.answer_ || d_.stop_; });
  d_.waiting_ = Waiting::kNone;
  if (!d_.answer_) return {Status::kUnavailable, "stopped"};
  host::StudyAnswer a = *d_.answer_;
  d_.answer_.reset();
  d_.PublishParticipant({{"state", "wait"}});
  return a;
}

void StudyDesk::Participant::Refused(const std::string& why) {
  std::lock_guard<std::mutex> lock(d_.mutex_);
  d_.PublishExperimenter({{"event", "refused"}, {"message", why}});
}

bool StudyDesk::Participant::Break(int done, int total) {
  std::unique_lock<std::mutex> lock(d_.mutex_);
  d_.waiting_ = Waiting::kBreak;
  d_.next_ = false;
  d_.PublishParticipant({{"state", "break"}, {"trials_done", done}, {"total", total}});
  d_.changed_.wait(lock, [&] { return d_.next_ || d_.stop_; });
  d_.waiting_ = Waiting::kNone;
  d_.PublishParticipant({{"state", "wait"}});
  return !d_.stop_;
}

}  // namespace palpa::serve
