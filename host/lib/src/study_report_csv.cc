// A study report's CSV files: every table of the page, with full-precision numbers.
#include <cmath>
#include <cstdio>

#include "palpa/host/study_report.h"

namespace palpa::host {
namespace {

/// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string Field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

/// A number for a machine: round-trip precision; empty for NaN (no value).
std::string Number(double v) {
  if (std::isnan(v)) return "";
  char b[32];
  std::snprintf(b, sizeof(b), "%.10g", v);
  return b;
}

std::string Row(std::initializer_list<std::string> fields) {
  std::string row;
  for (const std::string& f : fields) row += (row.empty() ? "" : ",") + Field(f);
  return row + "\n";
}

const char* const kTallyHeader =
    "trials,positions,tp,fp,tn,fn,se,se_lo,se_hi,se_n,sp,sp_lo,sp_hi,sp_n,ppv,ppv_lo,ppv_hi,ppv_n,"
    "acc,acc_lo,acc_hi,acc_n,mean_time_ms,sd_time_ms";

std::string Tally(const DetectionTally& t) {
  const DetectionCounts& c = t.counts;
  std::string s = std::to_string(t.trials) + "," + std::to_string(c.total()) + "," +
                  std::to_string(c.tp) + "," + std::to_string(c.fp) + "," + std::to_string(c.tn) +
                  "," + std::to_string(c.fn);
  for (const Proportion p : {Sensitivity(c), Specificity(c), Precision(c), Accuracy(c)}) {
    const Interval i = WilsonInterval(p);
    s += "," + Number(p.value()) + "," + Number(i.lo) + "," + Number(i.hi) + "," + Number(p.n);
  }
  double mean = 0, square = 0;
  for (double v : t.times_ms) mean += v / static_cast<double>(t.times_ms.size());
  for (double v : t.times_ms) square += (v - mean) * (v - mean);
  const double sd = t.times_ms.size() > 1
                        ? std::sqrt(square / static_cast<double>(t.times_ms.size() - 1))
                        : std::nan("");
  return s + "," + Number(t.times_ms.empty() ? std::nan("") : mean) + "," + Number(sd) + "\n";
}

std::string Sessions(const StudyAnalysis& a) {
  std::string csv =
      "dir,participant,complete,started_utc,finished_utc,seed,palpa_version,firmware_version,"
      "catalog_hash,config_crc,board,sim_seed,sim_unit,calibration_files,detection_trials,"
      "practice_trials,staircase_trials,warnings\n";
  for (const SessionSummary& s : a.summaries) {
    const SessionRecords& r = a.sessions[s.session];
    const StudyProvenance& p = r.session.provenance;
    std::string files, warnings;
    for (const auto& [name, hash] : p.calibration_files)
      files += (files.empty() ? "" : " ") + name + "=" + hash;
    for (const std::string& w : s.warnings) warnings += (warnings.empty() ? "" : "; ") + w;
    csv += Row({r.dir, r.session.participant, r.session.complete ? "true" : "false",
                r.session.started_utc, r.session.finished_utc.value_or(""),
                std::to_string(r.session.seed), p.palpa_version, p.firmware_version, p.catalog_hash,
                p.config_crc, p.board, p.sim ? std::to_string(p.sim->seed) : "",
                p.sim ? std::to_string(p.sim->unit) : "", files, std::to_string(s.detection_trials),
                std::to_string(s.practice_trials), std::to_string(s.staircase_trials), warnings});
  }
  return csv;
}

std::string Comparisons(const ModeComparison& c) {
  std::string csv =
      "metric,sequential,sequential_n,simultaneous,simultaneous_n,difference,combined_interval,"
      "significant,combined_interval_thesis_n,significant_thesis_n,wilcoxon_pairs,wilcoxon_w,"
      "wilcoxon_t,wilcoxon_p,wilcoxon_exact,wilcoxon_critical_t,wilcoxon_significant_by_table\n";
  for (const MetricComparison& m : c.metrics) {
    const WilcoxonResult& w = m.participants;
    csv += Row({m.metric, Number(m.sequential.value()), Number(m.sequential.n),
                Number(m.simultaneous.value()), Number(m.simultaneous.n),
                Number(m.by_own_n.difference), Number(m.by_own_n.combined),
                m.by_own_n.significant ? "true" : "false", Number(m.by_thesis_n.combined),
                m.by_thesis_n.significant ? "true" : "false", std::to_string(w.n), Number(w.w),
                Number(w.t), Number(w.p), w.exact ? "true" : "false",
                w.critical_t >= 0 ? std::to_string(w.critical_t) : "",
                w.significant_by_table ? "true" : "false"});
  }
  return csv;
}

std::string Times(const ModeComparison& c) {
  std::string csv = "test,n,statistic,df,p,mean_difference_ms\n";
  const auto t_row = [&](const char* name, const TTestResult& t, int n) {
    csv += Row({name, std::to_string(n), Number(t.t), Number(t.df), Number(t.p),
                Number(t.mean_difference)});
  };
  t_row("welch_t_trials", c.times_welch, c.trials_sequential + c.trials_simultaneous);
  t_row("paired_t_participant_means", c.times_paired, c.participants_paired);
  const WilcoxonResult& w = c.times_wilcoxon;
  csv += Row({"wilcoxon_participant_means", std::to_string(w.n), Number(w.t), "", Number(w.p), ""});
  return csv;
}

}  // namespace

std::vector<ReportFile> StudyReportCsv(const StudyAnalysis& a) {
  std::vector<ReportFile> files;
  files.push_back({"sessions.csv", Sessions(a)});
  std::string blocks = std::string("block,mode,") + kTallyHeader + "\n";
  for (const BlockSummary& b : a.blocks)
    blocks += Field(b.block) + "," + TrialModeName(b.mode) + "," + Tally(b.tally);
  files.push_back({"blocks.csv", blocks});
  std::string conditions = std::string("block,condition,mode,") + kTallyHeader + "\n";
  for (const ConditionSummary& c : a.conditions) {
    conditions += Field(c.block) + "," + Field(c.condition) + "," + TrialModeName(c.mode) + "," +
                  Tally(c.tally);
  }
  files.push_back({"conditions.csv", conditions});
  std::string participants = std::string("participant,mode,") + kTallyHeader + "\n";
  for (const ParticipantMode& p : a.participant_modes)
    participants += Field(p.participant) + "," + TrialModeName(p.mode) + "," + Tally(p.tally);
  files.push_back({"participants.csv", participants});
  if (a.comparison) {
    files.push_back({"comparisons.csv", Comparisons(*a.comparison)});
    files.push_back({"times.csv", Times(*a.comparison)});
  }
  std::string staircases =
      "participant,block,unit,trials,reversals,reversals_used,enough,jnd,reference,weber\n";
  for (const StaircaseSummary& s : a.staircases) {
    staircases +=
        Row({s.participant, s.block, s.unit, std::to_string(s.trials), std::to_string(s.reversals),
             std::to_string(s.reversals_used), s.enough ? "true" : "false", Number(s.jnd),
             Number(s.reference), Number(s.weber)});
  }
  files.push_back({"staircases.csv", staircases});
  return files;
}

}  // namespace palpa::host
