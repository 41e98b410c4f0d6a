// A study's report: one self-contained HTML page (tables and SVG charts, no scripts) and CSV
// files of every table, from its analysis (study_analysis.h). What each figure means:
// docs/studies.md, "Analysis".
#pragma once

#include <string>
#include <vector>

#include "palpa/host/outcome.h"
#include "palpa/host/study_analysis.h"

namespace palpa::host {

struct ReportFile {
  std::string name;  ///< "report.html", "blocks.csv", ...
  std::string text;
};

/// report.html, sessions.csv, blocks.csv, conditions.csv, participants.csv, comparisons.csv,
/// times.csv and staircases.csv.
std::vector<ReportFile> RenderStudyReport(const StudyAnalysis& a);
/// The CSV files alone (RenderStudyReport includes them).
std::vector<ReportFile> StudyReportCsv(const StudyAnalysis& a);

/// Writes each file whole into `dir` (which must exist): the paths written, or the first failure.
Result<std::vector<std::string>> WriteStudyReport(const StudyAnalysis& a, const std::string& dir);

/// "91.7 % [81.9, 96.4] (55/60)": a proportion with its Wilson interval, for people.
std::string ProportionText(Proportion p);

}  // namespace palpa::host
