// A study report's page: the modes compared, tables per block, condition and participant, the
// staircases' JNDs and every session's provenance, with SVG charts; and writing the files.
#include "palpa/host/study_report.h"

#include <algorithm>
#include <cmath>

#include "number_text.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace palpa::host {
namespace {

const char* const kModeColor[] = {"#1f77b4", "#d62728"};  // sequential, simultaneous

std::string E(const std::string& s) { return SvgEscape(s); }

std::string Percent(double v) { return Fixed(100 * v, 1); }

int ModeIndex(TrialMode m) { return m == TrialMode::kSequential ? 0 : 1; }

std::string Head(const std::vector<const char*>& columns) {
  std::string h = "<table><tr>";
  for (const char* c : columns) h += std::string("<th>") + c + "</th>";
  return h + "</tr>\n";
}

std::string Cells(const std::vector<std::string>& cells) {
  std::string h = "<tr>";
  for (const std::string& c : cells) h += "<td>" + c + "</td>";
  return h + "</tr>\n";
}

/// The four metrics and the mean time of a tally, as table cells.
std::vector<std::string> TallyCells(const DetectionTally& t) {
  const DetectionCounts& c = t.counts;
  double mean = 0;
  for (double v : t.times_ms) mean += v / 1000 / static_cast<double>(t.times_ms.size());
  return {std::to_string(t.trials),
          std::to_string(c.total()),
          ProportionText(Sensitivity(c)),
          ProportionText(Specificity(c)),
          ProportionText(Precision(c)),
          ProportionText(Accuracy(c)),
          Fixed(t.times_ms.empty() ? std::nan("") : mean, 2)};
}

/// A table of tallies: the leading columns, then the tally's.
std::string TallyHead(std::vector<const char*> columns) {
  for (const char* c : {"trials", "positions", "Se", "Sp", "PPV", "ACC", "mean time s"})
    columns.push_back(c);
  return Head(columns);
}

std::string TallyRow(std::vector<std::string> cells, const DetectionTally& t) {
  for (std::string& c : TallyCells(t)) cells.push_back(std::move(c));
  return Cells(cells);
}

std::string Verdict(bool significant) {
  return significant ? "<b>significant</b>" : "not significant";
}

std::string PValue(double p) {
  if (std::isnan(p)) return "—";
  char b[32];
  std::snprintf(b, sizeof(b), p < 1e-3 ? "%.2e" : "%.4f", p);
  return b;
}

/// Each metric by mode with its Wilson interval: a point and a vertical bar per mode.
std::string MetricsChart(const StudyAnalysis& a) {
  Chart c{"Detection by mode, with 95 % Wilson intervals",
          "metric: 1 Se, 2 Sp, 3 PPV, 4 ACC",
          "%",
          {},
          {},
          780,
          380,
          false};
  for (int mode = 0; mode < 2; ++mode) {
    Series points{
        mode == 0 ? "sequential" : "simultaneous", {}, kModeColor[mode], false, true, false};
    for (size_t i = 0; i < a.comparison->metrics.size(); ++i) {
      const MetricComparison& m = a.comparison->metrics[i];
      const Proportion p = mode == 0 ? m.sequential : m.simultaneous;
      if (std::isnan(p.value())) continue;
      const double x = static_cast<double>(i + 1) + (mode == 0 ? -0.1 : 0.1);
      const Interval w = WilsonInterval(p);
      points.points.push_back({x, 100 * p.value()});
      c.series.push_back(
          {"", {{x, 100 * w.lo}, {x, 100 * w.hi}}, kModeColor[mode], false, false, false});
    }
    c.series.push_back(points);
  }
  // Half a metric of room either side (an undrawn series), so no point sits on the frame.
  const double y = c.series.front().points.front().second;
  c.series.push_back({"", {{0.5, y}, {4.5, y}}, "none", false, false, false});
  return RenderSvg(c);
}

/// Each participant's accuracy and mean time in each mode.
std::string ParticipantsChart(const StudyAnalysis& a) {
  Chart accuracy{"", "participant (in the order of the table)", "ACC %", {}, {}, 780, 300, false};
  Chart time{"", "participant (in the order of the table)", "mean time s", {}, {}, 780, 300, false};
  std::vector<std::string> order;
  for (const ParticipantMode& p : a.participant_modes) {
    if (std::find(order.begin(), order.end(), p.participant) == order.end())
      order.push_back(p.participant);
  }
  for (int mode = 0; mode < 2; ++mode) {
    const char* name = mode == 0 ? "sequential" : "simultaneous";
    Series acc{name, {}, kModeColor[mode], false, true, false};
    Series t = acc;
    for (const ParticipantMode& p : a.participant_modes) {
      if (ModeIndex(p.mode) != mode) continue;
      const auto x = static_cast<double>(std::find(order.begin(), order.end(), p.participant) -
                                         order.begin() + 1);
      acc.points.push_back({x, 100 * Accuracy(p.tally.counts).value()});
      double mean = 0;
      for (double v : p.tally.times_ms) mean += v / 1000 / static_cast<double>(p.tally.trials);
      t.points.push_back({x, mean});
    }
    if (!acc.points.empty()) {
      accuracy.series.push_back(acc);
      time.series.push_back(t);
    }
  }
  return RenderSvgPanels({accuracy, time}, "Participants: accuracy and mean trial time");
}

std::string StaircaseChart(const StudyAnalysis& a) {
  Chart c{"Staircases: comparison − reference per trial",
          "trial",
          "comparison − reference (" + E(a.staircases.front().unit) + ")",
          {},
          {},
          780,
          360,
          false};
  for (const StaircaseSummary& s : a.staircases)
    c.series.push_back({s.participant + " " + s.block, s.track, "", false, false, false});
  return RenderSvg(c);
}

std::string Comparison(const StudyAnalysis& a) {
  const ModeComparison& c = *a.comparison;
  std::string h =
      "<h2>Sequential against simultaneous</h2>\n<p>Each metric pooled over participants with its "
      "Wilson interval; the difference against the combined interval (thesis eq 3.6), over each "
      "metric's own denominator and, as the thesis's printed intervals were, over every finger "
      "position; the Wilcoxon signed-rank test on the " +
      std::to_string(c.participants_paired) +
      " participants who ran both modes (their own values, paired).</p>\n";
  h += Head({"metric", "sequential", "simultaneous", "Δp", "combined interval", "verdict",
             "thesis n: interval", "verdict", "Wilcoxon n", "W", "T", "p", "T crit (α 0.05)",
             "verdict"});
  for (const MetricComparison& m : c.metrics) {
    const WilcoxonResult& w = m.participants;
    h += Cells({m.metric, ProportionText(m.sequential), ProportionText(m.simultaneous),
                Fixed(m.by_own_n.difference, 3), Fixed(m.by_own_n.combined, 3),
                Verdict(m.by_own_n.significant), Fixed(m.by_thesis_n.combined, 3),
                Verdict(m.by_thesis_n.significant), std::to_string(w.n), Fixed(w.w, 1),
                Fixed(w.t, 1), PValue(w.p) + (w.exact ? " exact" : " normal"),
                w.critical_t >= 0 ? std::to_string(w.critical_t) : "none",
                Verdict(w.significant_by_table)});
  }
  h += "</table>\n";
  const TTestResult& welch = c.times_welch;
  h += "<p>Trial times (one per trial, answer − settled on the board's clock): Welch's t-test "
       "on " +
       std::to_string(c.trials_sequential) + " sequential and " +
       std::to_string(c.trials_simultaneous) +
       " simultaneous trials: simultaneous − sequential = " +
       Fixed(welch.mean_difference / 1000, 3) + " s, t = " + Fixed(welch.t, 3) +
       ", df = " + Fixed(welch.df, 1) + ", p = " + PValue(welch.p) +
       ". Paired t-test on the participants' " + "mean times: t = " + Fixed(c.times_paired.t, 3) +
       ", p = " + PValue(c.times_paired.p) +
       "; Wilcoxon on them: T = " + Fixed(c.times_wilcoxon.t, 1) +
       ", p = " + PValue(c.times_wilcoxon.p) + ".</p>\n";
  return h + MetricsChart(a);
}

std::string Provenance(const StudyAnalysis& a) {
  std::string h = "<h2>Sessions</h2>\n" +
                  Head({"directory", "participant", "started", "finished", "seed", "palpa",
                        "firmware", "catalog", "config CRC", "board", "calibration files",
                        "trials (detection, practice, staircase)"});
  for (const SessionSummary& s : a.summaries) {
    const SessionRecords& r = a.sessions[s.session];
    const StudyProvenance& p = r.session.provenance;
    std::string files;
    for (const auto& [name, hash] : p.calibration_files)
      files += E(name) + " " + E(hash.substr(0, 12)) + "…<br>";
    h += Cells({E(r.dir), E(r.session.participant), E(r.session.started_utc),
                r.session.finished_utc ? E(*r.session.finished_utc) : "<b>not finished</b>",
                std::to_string(r.session.seed), E(p.palpa_version), E(p.firmware_version),
                E(p.catalog_hash), E(p.config_crc),
                E(p.board) + (p.sim ? " (seed " + std::to_string(p.sim->seed) + ", unit " +
                                          std::to_string(p.sim->unit) + ")"
                                    : ""),
                files.empty() ? "none" : files,
                std::to_string(s.detection_trials) + ", " + std::to_string(s.practice_trials) +
                    ", " + std::to_string(s.staircase_trials)});
  }
  return h + "</table>\n";
}

}  // namespace

std::string ProportionText(Proportion p) {
  if (!(p.n > 0)) return "—";
  const Interval w = WilsonInterval(p);
  return Percent(p.value()) + " % [" + Percent(w.lo) + ", " + Percent(w.hi) + "] (" + Num(p.k) +
         "/" + Num(p.n) + ")";
}

std::vector<ReportFile> RenderStudyReport(const StudyAnalysis& a) {
  std::string h =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>palpa study " + E(a.study) +
      "</title><style>body{font-family:sans-serif;max-width:1400px;margin:2em auto}"
      "td,th{padding:2px 6px;text-align:right}table{border-collapse:collapse;font-size:85%}"
      "tr:nth-child(even){background:#f4f4f4}</style></head><body>\n<h1>Study " +
      E(a.study) + "</h1>\n<p>" + std::to_string(a.sessions.size()) +
      " sessions pooled. Unit of analysis: each finger position of each non-practice detection "
      "trial is one TP, FP, TN or FN; one time per trial. Percentages with their 95 % Wilson "
      "score interval and k/n. The CSV files beside this page hold every table.</p>\n";
  if (!a.notes.empty()) {
    h += "<p><b>Notes:</b></p><ul>";
    for (const std::string& n : a.notes) h += "<li>" + E(n) + "</li>";
    h += "</ul>\n";
  }
  if (a.comparison) h += Comparison(a);
  h += "<h2>Blocks</h2>\n" + TallyHead({"block", "mode"});
  for (const BlockSummary& b : a.blocks)
    h += TallyRow({E(b.block), TrialModeName(b.mode)}, b.tally);
  h += "</table>\n<h2>Conditions</h2>\n" + TallyHead({"block", "condition", "mode"});
  for (const ConditionSummary& c : a.conditions)
    h += TallyRow({E(c.block), E(c.condition), TrialModeName(c.mode)}, c.tally);
  h += "</table>\n<h2>Participants</h2>\n" + TallyHead({"participant", "mode"});
  for (const ParticipantMode& p : a.participant_modes)
    h += TallyRow({E(p.participant), TrialModeName(p.mode)}, p.tally);
  h += "</table>\n";
  if (!a.participant_modes.empty()) h += ParticipantsChart(a);
  if (!a.staircases.empty()) {
    h += "<h2>Staircases</h2>\n<p>JND: the mean |comparison − reference| over the last "
         "reversals (as many as the study says); Weber fraction: JND / reference.</p>\n" +
         Head({"participant", "block", "trials", "reversals", "used", "JND", "reference",
               "Weber fraction"});
    for (const StaircaseSummary& s : a.staircases) {
      h += Cells({E(s.participant), E(s.block), std::to_string(s.trials),
                  std::to_string(s.reversals) + (s.enough ? "" : " <b>(too few)</b>"),
                  std::to_string(s.reversals_used), Fixed(s.jnd, 3) + " " + E(s.unit),
                  Fixed(s.reference, 3) + " " + E(s.unit), Fixed(s.weber, 3)});
    }
    h += "</table>\n" + StaircaseChart(a);
  }
  h += Provenance(a) + "</body></html>\n";
  std::vector<ReportFile> files = {{"report.html", h}};
  for (ReportFile& f : StudyReportCsv(a)) files.push_back(std::move(f));
  return files;
}

Result<std::vector<std::string>> WriteStudyReport(const StudyAnalysis& a, const std::string& dir) {
  std::vector<std::string> paths;
  for (const ReportFile& f : RenderStudyReport(a)) {
    paths.push_back(dir + "/" + f.name);
    if (const Outcome written = WriteFileWhole(paths.back(), f.text); !written.ok()) return written;
  }
  return paths;
}

}  // namespace palpa::host
