// A served study session: the runner's participant is the page (each callback waits on the API),
// its triggers and records become notifications, and what the participant's view is told is
// built here from the prompt alone — never a condition, a stimulus or a correctness.
#include "study_desk.h"

#include <chrono>

namespace palpa::serve {
namespace {

// File-local: other files of the unity batch alias Json in their own.
using Json = rpc::Json;
using host::Outcome;
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

/// Whether the participant's answer matched the condition (every finger position, as scored).
bool Correct(const Json& record) {
  if (record.value("kind", "") == "staircase") return record["staircase"].value("correct", false);
  return record["answer"]["fingers"] == record["expected"];
}

}  // namespace

class StudyDesk::Participant final : public host::StudyParticipant {
 public:
  explicit Participant(StudyDesk& d) : d_(d) {}

  void Feel(const host::TrialPrompt& t, int finger, host::BoardClock& clock,
            double until_s) override {
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

  host::Result<host::StudyAnswer> Answer(const host::TrialPrompt& t, host::BoardClock&) override {
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

  void Refused(const std::string& why) override {
    std::lock_guard<std::mutex> lock(d_.mutex_);
    d_.PublishExperimenter({{"event", "refused"}, {"message", why}});
  }

  bool Break(int done, int total) override {
    std::unique_lock<std::mutex> lock(d_.mutex_);
    d_.waiting_ = Waiting::kBreak;
    d_.next_ = false;
    d_.PublishParticipant({{"state", "break"}, {"trials_done", done}, {"total", total}});
    d_.changed_.wait(lock, [&] { return d_.next_ || d_.stop_; });
    d_.waiting_ = Waiting::kNone;
    d_.PublishParticipant({{"state", "wait"}});
    return !d_.stop_;
  }

 private:
  StudyDesk& d_;
};

StudyDesk::~StudyDesk() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    changed_.notify_all();
  }
  if (thread_.joinable()) thread_.join();
}

Outcome StudyDesk::Start(host::Device& device, const host::Study& study,
                         const std::string& participant, const std::string& out_dir,
                         const std::string& shown_dir, bool resume) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (running_) {
    return Outcome::Fail(Status::kBusy,
                         "a session is running (" + session_["study"].get<std::string>() +
                             ", participant " + session_["participant"].get<std::string>() +
                             "): study.stop first");
  }
  if (thread_.joinable()) {  // the last session's thread has ended: collect it
    lock.unlock();
    thread_.join();
    lock.lock();
  }
  stop_ = false;
  running_ = true;
  started_ = ended_ = false;
  session_ = {{"running", true},         {"study", study.name},   {"participant", participant},
              {"out_dir", shown_dir},    {"resume", resume},      {"complete", false},
              {"message", ""},           {"provenance", nullptr}, {"order", Json::array()},
              {"records", Json::array()}};
  host::StudyRunOptions o;
  o.out_dir = out_dir;
  o.participant = participant;
  o.resume = resume;
  o.board = options_.board;
  o.sim = options_.sim;
  o.calibration_dir = options_.calibration_dir;
  o.use_calibrations = options_.use_calibrations;
  o.on_trigger = [this](const host::TriggerEvent& e) {
    if (options_.on_trigger) options_.on_trigger(e);  // first, and unlocked: the edge is the moment
    OnTrigger(e);
  };
  o.progress = [this](const std::string& line) { OnProgress(line); };
  o.stopped = [this] { return stop_.load(); };
  o.on_started = [this, out_dir] {
    const auto read = host::ReadSessionDir(out_dir);
    std::lock_guard<std::mutex> hold(mutex_);
    started_ = true;
    if (read.ok()) {
      const Json s = host::SessionToJson(read.value.session);
      session_["provenance"] = s["provenance"];
      session_["order"] = s["order"];
      for (const host::TrialRecord& t : read.value.trials) {
        Json r = host::TrialToJson(t);
        r["correct"] = Correct(r);
        session_["records"].push_back(std::move(r));
      }
    }
    PublishExperimenter({{"event", "started"}, {"session", session_}});
    PublishParticipant({{"state", "wait"}});
    changed_.notify_all();
  };
  thread_ = std::thread([this, &device, study, o] { Run(device, study, o); });
  changed_.wait(lock, [&] { return started_ || ended_; });
  if (started_) return {};
  const Outcome refused = end_;
  lock.unlock();
  thread_.join();
  return refused;
}

void StudyDesk::Run(host::Device& device, host::Study study, host::StudyRunOptions o) {
  Participant participant(*this);
  const Outcome r = host::RunStudy(device, study, participant, o);
  std::lock_guard<std::mutex> lock(mutex_);
  running_ = false;
  ended_ = true;
  end_ = r;
  waiting_ = Waiting::kNone;
  if (started_) {  // a refused start is the caller's answer, and nobody else's news
    session_["running"] = false;
    session_["complete"] = r.ok();
    session_["message"] = r.ok() ? "complete" : r.message;
    PublishExperimenter({{"event", "finished"},
                         {"complete", r.ok()},
                         {"message", session_["message"]},
                         {"trials", session_["records"].size()},
                         {"out_dir", session_["out_dir"]}});
    PublishParticipant({{"state", r.ok() ? "finished" : "stopped"}});
  }
  changed_.notify_all();
}

Outcome StudyDesk::Answer(int trial, const host::StudyAnswer& answer) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!running_) return Outcome::Fail(Status::kInvalidArgument, "no study session is running");
  if (waiting_ != Waiting::kAnswer) {
    return Outcome::Fail(Status::kInvalidArgument,
                         "no trial is waiting for an answer now (the display is settling, a "
                         "finger is shown alone, or the session is at a break)");
  }
  if (trial != prompt_.index) {
    return Outcome::Fail(Status::kInvalidArgument, "'trial': " + std::to_string(trial) +
                                                       " is not the trial asked (" +
                                                       std::to_string(prompt_.index) + " is)");
  }
  if (answer_) {  // handed over, not yet taken: the first answer stands
    return Outcome::Fail(Status::kInvalidArgument,
                         "trial " + std::to_string(trial) + " is answered already");
  }
  if (const Outcome check = host::CheckAnswer(prompt_, answer); !check.ok()) return check;
  answer_ = answer;
  changed_.notify_all();
  return {};
}

Outcome StudyDesk::Next(int trial) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!running_) return Outcome::Fail(Status::kInvalidArgument, "no study session is running");
  const bool feel = waiting_ == Waiting::kFeel && trial == prompt_.index;
  if (!feel && waiting_ != Waiting::kBreak) {
    return Outcome::Fail(Status::kInvalidArgument,
                         "nothing to move on from: trial " + std::to_string(trial) +
                             " shows no finger alone now, and the session is not at a break");
  }
  next_ = true;
  changed_.notify_all();
  return {};
}

Outcome StudyDesk::Stop(const std::string& why) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!running_) return Outcome::Fail(Status::kInvalidArgument, "no study session is running");
  stop_ = true;
  PublishExperimenter({{"event", "stopping"}, {"reason", why}});
  changed_.notify_all();
  return {};
}

bool StudyDesk::running() {
  std::lock_guard<std::mutex> lock(mutex_);
  return running_;
}

Json StudyDesk::ParticipantState() {
  std::lock_guard<std::mutex> lock(mutex_);
  return participant_;
}

Json StudyDesk::ExperimenterState() {
  std::lock_guard<std::mutex> lock(mutex_);
  return session_.is_null() ? Json{{"running", false}} : session_;
}

std::vector<Json> StudyDesk::Take() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Json> out(std::make_move_iterator(queue_.begin()),
                        std::make_move_iterator(queue_.end()));
  queue_.clear();
  return out;
}

void StudyDesk::PublishParticipant(Json state) {
  state["seq"] = ++seq_;
  state["done"] = session_.is_null() ? 0 : session_["records"].size();
  state["total"] = session_.is_null() ? 0 : session_["order"].size();
  participant_ = state;
  queue_.push_back({{"channel", "study.participant"},
                    {"method", "notify_study_participant"},
                    {"params", std::move(state)}});
}

void StudyDesk::PublishExperimenter(Json params) {
  queue_.push_back({{"channel", "study.experimenter"},
                    {"method", "notify_study"},
                    {"params", std::move(params)}});
}

void StudyDesk::OnTrigger(const host::TriggerEvent& e) {
  std::lock_guard<std::mutex> lock(mutex_);
  PublishExperimenter(
      {{"event", "trigger"}, {"kind", e.kind}, {"trial", e.trial}, {"board_ms", e.board_ms}});
  if (e.kind != "settled") return;
  const Json& order = session_["order"];
  Json started = {{"event", "trial_started"}, {"trial", e.trial}, {"board_ms", e.board_ms}};
  for (const Json& t : order) {
    if (t.value("index", -1) != e.trial) continue;
    started["block"] = t["block"];
    started["condition"] = t["condition"];
    started["practice"] = t["practice"];
  }
  PublishExperimenter(std::move(started));
}

void StudyDesk::OnProgress(const std::string& line) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (line.empty() || line[0] != '{') {
    PublishExperimenter({{"event", "note"}, {"message", line}});
    return;
  }
  Json record = Json::parse(line, nullptr, false);
  if (record.is_discarded()) return;
  record["correct"] = Correct(record);
  session_["records"].push_back(record);
  PublishExperimenter({{"event", "trial_answered"}, {"record", std::move(record)}});
}

}  // namespace palpa::serve
