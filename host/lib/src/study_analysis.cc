// A study's analysis: sessions pooled (one study, each participant once), detection tallies per
// block, condition and participant, the two modes compared, and staircase JNDs.
#include "palpa/host/study_analysis.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace palpa::host {
namespace {

using nlohmann::json;

/// The entry of `list` that `match` finds, appended from `make` when there is none (first
/// appearance keeps the order the sessions ran them in).
template <typename T, typename Match, typename Make>
T& Find(std::vector<T>& list, Match match, Make make) {
  const auto it = std::find_if(list.begin(), list.end(), match);
  if (it != list.end()) return *it;
  list.push_back(make());
  return list.back();
}

/// The first top-level field where two study definitions differ.
std::string FirstDifference(const json& a, const json& b) {
  for (auto it = a.begin(); it != a.end(); ++it) {
    if (!b.contains(it.key()) || b.at(it.key()) != it.value()) return it.key();
  }
  for (auto it = b.begin(); it != b.end(); ++it) {
    if (!a.contains(it.key())) return it.key();
  }
  return "";
}

Outcome CheckOneStudy(const std::vector<SessionRecords>& sessions) {
  const SessionRecords& first = sessions.front();
  std::map<std::string, std::string> participants;  // id → directory
  for (const SessionRecords& s : sessions) {
    const std::string name = s.session.StudyName();
    if (name != first.session.StudyName()) {
      return Outcome::Fail(Status::kInvalidArgument,
                           s.dir + ": study \"" + name + "\", but " + first.dir + " is study \"" +
                               first.session.StudyName() +
                               "\": a report pools the sessions of one study");
    }
    if (s.session.study != first.session.study) {
      return Outcome::Fail(
          Status::kInvalidArgument,
          s.dir + ": study \"" + name + "\" was run with another definition than " + first.dir +
              "'s (study." + FirstDifference(first.session.study, s.session.study) +
              " differs): a report pools the sessions of one study");
    }
    const auto [other, fresh] = participants.emplace(s.session.participant, s.dir);
    if (!fresh) {
      return Outcome::Fail(Status::kInvalidArgument, s.dir + ": participant \"" +
                                                         s.session.participant + "\" is in " +
                                                         other->second + " already");
    }
  }
  return {};
}

/// The staircase block's reversals_used (study.blocks[i].staircase, as the runner wrote the study):
/// how many of the last reversals the JND averages.
Result<int> ReversalsUsed(const SessionRecords& s, const std::string& block) {
  const json& study = s.session.study;
  const std::string where = s.dir + "/" + kSessionFileName + ": ";
  const json* blocks = study.contains("blocks") ? &study["blocks"] : nullptr;
  if (blocks != nullptr && blocks->is_array()) {
    for (size_t i = 0; i < blocks->size(); ++i) {
      const json& b = (*blocks)[i];
      if (!b.is_object() || !b.contains("name") || b["name"] != block) continue;
      const std::string field = "study.blocks[" + std::to_string(i) + "].staircase.reversals_used";
      const json* v = b.contains("staircase") && b["staircase"].is_object() &&
                              b["staircase"].contains("reversals_used")
                          ? &b["staircase"]["reversals_used"]
                          : nullptr;
      if (v == nullptr || !v->is_number_integer() || v->get<long>() < 1 || v->get<long>() > 1000) {
        return Outcome::Fail(Status::kInvalidArgument,
                             where + field +
                                 ": must be an integer, 1 … 1000 (the staircase's JND averages "
                                 "that many last reversals)");
      }
      return static_cast<int>(v->get<long>());
    }
  }
  return Outcome::Fail(Status::kInvalidArgument,
                       where + "study.blocks: no block \"" + block +
                           "\", which trials.jsonl's staircase trials name");
}

void Finish(StaircaseSummary& s, const std::vector<const TrialRecord*>& trials) {
  std::vector<const TrialRecord*> reversals;
  for (const TrialRecord* t : trials) {
    s.track.push_back(
        {static_cast<double>(++s.trials), t->staircase.comparison - t->staircase.reference});
    if (t->staircase.reversal) reversals.push_back(t);
    s.unit = t->staircase.unit;
  }
  s.reversals = static_cast<int>(reversals.size());
  s.enough = s.reversals >= s.reversals_used;
  const size_t used = std::min(reversals.size(), static_cast<size_t>(s.reversals_used));
  if (used == 0) {
    s.jnd = s.reference = s.weber = std::nan("");
    return;
  }
  double jnd = 0, reference = 0;
  for (size_t i = reversals.size() - used; i < reversals.size(); ++i) {
    jnd += std::fabs(reversals[i]->staircase.comparison - reversals[i]->staircase.reference);
    reference += reversals[i]->staircase.reference;
  }
  s.jnd = jnd / static_cast<double>(used);
  s.reference = reference / static_cast<double>(used);
  s.weber = s.reference != 0 ? s.jnd / std::fabs(s.reference) : std::nan("");
}

void Compare(StudyAnalysis& a) {
  DetectionTally by_mode[2];
  for (const BlockSummary& b : a.blocks) {
    DetectionTally& t = by_mode[b.mode == TrialMode::kSequential ? 0 : 1];
    t.counts += b.tally.counts;
    t.trials += b.tally.trials;
    t.times_ms.insert(t.times_ms.end(), b.tally.times_ms.begin(), b.tally.times_ms.end());
  }
  if (by_mode[0].trials == 0 || by_mode[1].trials == 0) return;
  // Participants who ran both modes, for the paired tests.
  std::vector<std::pair<const DetectionTally*, const DetectionTally*>> pairs;
  for (const ParticipantMode& p : a.participant_modes) {
    if (p.mode != TrialMode::kSequential) continue;
    for (const ParticipantMode& q : a.participant_modes) {
      if (q.participant == p.participant && q.mode == TrialMode::kSimultaneous)
        pairs.push_back({&p.tally, &q.tally});
    }
  }
  ModeComparison c;
  const std::pair<const char*, Proportion (*)(const DetectionCounts&)> metrics[] = {
      {"Se", Sensitivity}, {"Sp", Specificity}, {"PPV", Precision}, {"ACC", Accuracy}};
  for (const auto& [name, metric] : metrics) {
    MetricComparison m;
    m.metric = name;
    m.sequential = metric(by_mode[0].counts);
    m.simultaneous = metric(by_mode[1].counts);
    m.by_own_n = CompareProportions(m.sequential, m.simultaneous);
    const auto all = [](Proportion p, const DetectionCounts& k) {
      const auto n = static_cast<double>(k.total());
      return Proportion{p.value() * n, n};
    };
    m.by_thesis_n = CompareProportions(all(m.sequential, by_mode[0].counts),
                                       all(m.simultaneous, by_mode[1].counts));
    std::vector<double> first, second;
    for (const auto& [seq, sim] : pairs) {
      const double x = metric(seq->counts).value(), y = metric(sim->counts).value();
      if (std::isnan(x) || std::isnan(y)) continue;
      first.push_back(x);
      second.push_back(y);
    }
    m.participants = WilcoxonSignedRank(first, second);
    m.participants_paired = static_cast<int>(first.size());
    c.metrics.push_back(m);
  }
  c.trials_sequential = by_mode[0].trials;
  c.trials_simultaneous = by_mode[1].trials;
  c.times_welch = WelchTTest(by_mode[0].times_ms, by_mode[1].times_ms);
  std::vector<double> first, second;
  for (const auto& [seq, sim] : pairs) {
    auto mean = [](const std::vector<double>& x) {
      double sum = 0;
      for (double v : x) sum += v;
      return sum / static_cast<double>(x.size());
    };
    first.push_back(mean(seq->times_ms));
    second.push_back(mean(sim->times_ms));
  }
  c.times_paired = PairedTTest(first, second);
  c.times_wilcoxon = WilcoxonSignedRank(first, second);
  c.participants_paired = static_cast<int>(pairs.size());
  a.comparison = c;
}

}  // namespace

void DetectionTally::Add(const TrialRecord& t) {
  for (size_t i = 0; i < t.expected.size(); ++i) {
    const bool expected = t.expected[i], marked = t.answer.fingers[i];
    ++(expected ? (marked ? counts.tp : counts.fn) : (marked ? counts.fp : counts.tn));
  }
  ++trials;
  times_ms.push_back(static_cast<double>(t.time_ms));
}

Result<StudyAnalysis> AnalyseStudy(std::vector<SessionRecords> sessions) {
  if (sessions.empty()) return Outcome::Fail(Status::kInvalidArgument, "no session to analyse");
  if (const Outcome one = CheckOneStudy(sessions); !one.ok()) return one;
  StudyAnalysis a;
  a.study = sessions.front().session.StudyName();
  a.sessions = std::move(sessions);
  for (size_t k = 0; k < a.sessions.size(); ++k) {
    const SessionRecords& s = a.sessions[k];
    SessionSummary summary{k, 0, 0, 0, s.warnings};
    const std::string& who = s.session.participant;
    std::map<std::string, std::vector<const TrialRecord*>> staircases;  // by block
    std::vector<std::string> staircase_order;
    for (const TrialRecord& t : s.trials) {
      if (t.practice) {
        ++summary.practice_trials;
        continue;
      }
      if (t.kind == TrialKind::kStaircase) {
        ++summary.staircase_trials;
        if (!staircases.count(t.block)) staircase_order.push_back(t.block);
        staircases[t.block].push_back(&t);
        continue;
      }
      // Records read from a directory always pass; ones a program built are checked here.
      if (!t.mode || !t.condition || t.answer.fingers.size() != t.expected.size()) {
        return Outcome::Fail(Status::kInvalidArgument,
                             s.dir + ": trial " + std::to_string(t.index) +
                                 ": a detection trial needs a mode, a condition and an answer "
                                 "for each finger position");
      }
      ++summary.detection_trials;
      const TrialMode mode = *t.mode;
      Find(
          a.blocks, [&](const BlockSummary& b) { return b.block == t.block && b.mode == mode; },
          [&] {
            return BlockSummary{t.block, mode, {}};
          })
          .tally.Add(t);
      Find(
          a.conditions,
          [&](const ConditionSummary& c) {
            return c.block == t.block && c.condition == *t.condition && c.mode == mode;
          },
          [&] {
            return ConditionSummary{t.block, *t.condition, mode, {}};
          })
          .tally.Add(t);
      Find(
          a.participant_modes,
          [&](const ParticipantMode& p) { return p.participant == who && p.mode == mode; },
          [&] {
            return ParticipantMode{who, mode, {}};
          })
          .tally.Add(t);
    }
    for (const std::string& block : staircase_order) {
      const Result<int> used = ReversalsUsed(s, block);
      if (!used.ok()) return used.outcome();
      StaircaseSummary st;
      st.participant = who;
      st.block = block;
      st.reversals_used = used.value;
      Finish(st, staircases[block]);
      a.staircases.push_back(st);
    }
    if (!s.session.complete) {
      a.notes.push_back(s.dir + ": the session of " + who +
                        " did not complete; its recorded trials are included");
    }
    for (const std::string& w : s.warnings) a.notes.push_back(w);
    a.summaries.push_back(summary);
  }
  Compare(a);
  return a;
}

}  // namespace palpa::host
