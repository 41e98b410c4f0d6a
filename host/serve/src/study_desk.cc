// A served study session: the runner on a thread of its own, its triggers and records become
// notifications, the experimenter's view of the session; the participant is the page
// (study_desk_participant.cc).
#include "study_desk.h"

#include "study_desk_participant.h"

namespace palpa::serve {
namespace {

// File-local: other files of the unity batch alias Json in their own.
using Json = rpc::Json;
using host::Outcome;
using host::Status;

/// Whether the participant's answer matched the condition (every finger position, as scored).
bool Correct(const Json& record) {
  if (record.value("kind", "") == "staircase") return record["staircase"].value("correct", false);
  return record["answer"]["fingers"] == record["expected"];
}

}  // namespace

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
