// The session: claim the output directory (or resume the session in it), then play the plan
// trial by trial, journalling each, and leave the board released whatever happens.
#include "palpa/host/study_runner.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <set>

#include "study_session.h"

namespace palpa::host {
namespace {

namespace fs = std::filesystem;

/// A fresh directory (missing, or empty) for a new session (none returned); the records in it
/// for a resumed one.
Result<std::optional<SessionRecords>> Claim(const Study& study, const StudyRunOptions& o,
                                            std::vector<std::string>* notes) {
  const std::string& dir = o.out_dir;
  std::error_code ec;
  const bool exists = fs::exists(dir, ec);
  const bool has_session = exists && fs::exists(fs::path(dir) / kSessionFileName, ec);
  if (!o.resume) {
    if (has_session) {
      const auto r = ReadSessionDir(dir);
      const bool complete = r.ok() && r.value.session.complete;
      return {
          Status::kInvalidArgument,
          dir + " already holds " +
              (!r.ok() ? std::string("a session (unreadable: ") + r.message + ")"
                       : (complete ? "a complete" : "an incomplete") +
                             std::string(" session of participant ") + r.value.session.participant +
                             " (" + std::to_string(r.value.trials.size()) + " trials)") +
              ": a participant id and its directory are used once" +
              (complete ? "" : "; --resume continues it")};
    }
    if (exists && (!fs::is_directory(dir, ec) || !fs::is_empty(dir, ec)))
      return {Status::kInvalidArgument,
              dir + ": not an empty directory (a session goes in one of its own)"};
    fs::create_directories(dir, ec);
    if (ec) return {Status::kIoError, dir + ": " + ec.message()};
    return std::optional<SessionRecords>{};
  }
  if (!has_session) return {Status::kNotFound, dir + " holds no session to resume"};
  auto r = ReadSessionDir(dir);
  if (!r.ok()) return r.outcome();
  const StudySession& s = r.value.session;
  if (s.complete) return {Status::kInvalidArgument, dir + ": the session is complete"};
  if (s.participant != o.participant) {
    return {Status::kInvalidArgument,
            dir + " is participant " + s.participant + "'s session, not " + o.participant + "'s"};
  }
  if (nlohmann::json(StudyToJson(study)) != s.study) {
    return {Status::kInvalidArgument,
            dir + ": the session ran study " + s.StudyName() +
                " as it was defined then; this definition differs (the order and the records "
                "would not match)"};
  }
  for (const std::string& w : r.value.warnings) notes->push_back(w);
  return std::optional<SessionRecords>(std::move(r.value));
}

class Released {
 public:
  explicit Released(Device& d) : d_(d) {}
  ~Released() { d_.Release(); }

 private:
  Device& d_;
};

}  // namespace

Outcome CheckParticipant(const std::string& id) {
  const bool ok = !id.empty() && id.size() <= 64 &&
                  id.find_first_not_of(
                      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                      "0123456789_.-") == std::string::npos &&
                  id[0] != '.' && id[0] != '-';
  if (ok) return {};
  return Outcome::Fail(Status::kInvalidArgument,
                       "participant \"" + id +
                           "\": 1 to 64 letters, digits, '_', '.' or '-', not starting with "
                           "'.' or '-'");
}

Outcome RunStudy(Device& device, const Study& study, StudyParticipant& participant,
                 const StudyRunOptions& o) {
  if (const Outcome p = CheckParticipant(o.participant); !p.ok()) return p;
  if (const Outcome b = CheckBoardForStudy(device, study); !b.ok()) return b;
  nlohmann::ordered_json settle;
  const auto lines = StudyLines(device, study, &settle);
  if (!lines.ok()) return lines.outcome();
  auto provenance = Provenance(device, study, o);
  if (!provenance.ok()) return provenance.outcome();
  provenance.value.extra["settle"] = settle;
  std::vector<std::string> notes;
  auto claimed = Claim(study, o, &notes);
  if (!claimed.ok()) return claimed.outcome();
  StudySession session;
  std::vector<TrialRecord> records;
  if (!claimed.value) {
    session.study = StudyToJson(study);
    session.participant = o.participant;
    session.seed = StudySeed(study, o.participant);
    for (const ScheduledTrial& t : PlanStudy(study, session.seed).trials) {
      session.order.push_back(
          {t.index, study.blocks[static_cast<size_t>(t.block)].name,
           t.condition < 0 ? "staircase" : study.conditions[static_cast<size_t>(t.condition)].name,
           t.practice});
    }
    session.provenance = provenance.value;
    session.started_utc = UtcNow();
  } else {  // the board may differ this time: each resumption says what it ran on
    session = claimed.value->session;
    records = claimed.value->trials;
    StudySession now;
    now.provenance = provenance.value;
    nlohmann::json resumed = SessionToJson(now)["provenance"];
    resumed["utc"] = UtcNow();
    session.extra["resumed"].push_back(resumed);
  }
  if (const Outcome w = WriteSession(o.out_dir, session); !w.ok()) return w;
  if (o.on_started) o.on_started();
  const StudyPlan plan = PlanStudy(study, session.seed);

  // What is done, and where each staircase stands.
  std::set<int> done;
  std::vector<StaircaseState> stairs(study.blocks.size());
  for (size_t b = 0; b < study.blocks.size(); ++b) {
    const Staircase& s = study.blocks[b].staircase;
    stairs[b].difference = std::fabs(s.start - s.reference);
  }
  for (const TrialRecord& t : records) {
    const int i = static_cast<int>(t.index);
    if (i < 0 || i >= static_cast<int>(plan.trials.size()) || !done.insert(i).second)
      return Outcome::Fail(Status::kInvalidArgument, o.out_dir + "/" + kTrialsFileName +
                                                         ": trial index " + std::to_string(i) +
                                                         " is not one of the plan's, or twice");
    const ScheduledTrial& p = plan.trials[static_cast<size_t>(i)];
    if (study.blocks[p.block].kind == BlockKind::kStaircase && !p.practice)
      stairs[p.block].Answer(study.blocks[p.block].staircase, t.staircase.correct);
  }
  for (const std::string& n : notes)
    if (o.progress) o.progress(n);

  Released released(device);
  TelemetryClock clock(device,
                       SettleRule(lines.value, study.tolerance_kpa * 1000, study.band_kpa * 1000,
                                  study.hold_ms / 1000.0),
                       o.stopped);
  const int total = static_cast<int>(plan.trials.size());
  bool played_any = false;
  for (const ScheduledTrial& t : plan.trials) {
    const StudyBlock& block = study.blocks[t.block];
    if (done.count(t.index)) continue;
    if (block.kind == BlockKind::kStaircase && !t.practice && stairs[t.block].done(block.staircase))
      continue;  // its reversals are in
    if (o.stopped && o.stopped())
      return Outcome::Fail(Status::kUnavailable, "stopped after " + std::to_string(done.size()) +
                                                     " trials: --resume continues");
    if (t.break_before || (!played_any && !done.empty())) {
      device.Release();
      if (!participant.Break(static_cast<int>(done.size()), total))
        return Outcome::Fail(Status::kUnavailable, "stopped at a break after " +
                                                       std::to_string(done.size()) +
                                                       " trials: --resume continues");
    }
    const Result<TrialRecord> r =
        PlayTrial(device, study, t, total, participant, clock, &stairs[t.block], o);
    if (!r.ok()) {
      Outcome failed = r.outcome();
      failed.message = "trial " + std::to_string(t.index + 1) + " of " + std::to_string(total) +
                       ": " + failed.message + " (" + std::to_string(done.size()) +
                       " trials kept; --resume continues)";
      return failed;
    }
    const Outcome a = AppendTrial(o.out_dir, r.value);
    if (!a.ok()) return a;
    for (const std::string& n : a.notes)
      if (o.progress) o.progress(n);
    done.insert(t.index);
    played_any = true;
    if (block.kind == BlockKind::kStaircase && !t.practice)
      stairs[t.block].Answer(block.staircase, r.value.staircase.correct);
    if (o.progress) o.progress(TrialLine(r.value));
  }
  session.finished_utc = UtcNow();
  session.complete = true;
  return WriteSession(o.out_dir, session);
}

}  // namespace palpa::host
