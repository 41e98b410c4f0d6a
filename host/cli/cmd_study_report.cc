// palpa study report: the sessions of one study analysed into an HTML report and CSV files.
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <set>
#include <system_error>

#include "cli.h"
#include "palpa/host/study_report.h"

namespace palpa::cli {
namespace {

/// STUDY-report in the working directory, the study's name made a plain file name.
std::string DefaultOut(const std::string& study) {
  std::string name = study;
  for (char& ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.')
      ch = '_';
  }
  if (name.front() == '.') name.front() = '_';
  return name + "-report";
}

}  // namespace

int CmdStudyReport(Context&, const std::vector<std::string>& args) {
  const char* what = "study report";
  std::vector<std::string> dirs;
  std::string out;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out") {
      const auto value = OptionValue(args, i++);
      if (!value.ok()) return Usage(what, value.message);
      out = value.value;
    } else if (!args[i].empty() && args[i][0] == '-') {
      return Usage(what, "unknown option '" + args[i] + "' (--out OUT)");
    } else {
      for (const std::string& d : dirs) {
        if (std::filesystem::path(d).lexically_normal() ==
            std::filesystem::path(args[i]).lexically_normal())
          return Usage(what, args[i] + ": named twice (each session once)");
      }
      dirs.push_back(args[i]);
    }
  }
  if (dirs.empty()) return Usage(what, "needs at least one session directory DIR");

  std::vector<host::SessionRecords> sessions;
  for (const std::string& dir : dirs) {
    auto read = host::ReadSessionDir(dir);
    if (!read.ok()) return Fail(what, read.status, read.message, kExitUsage);
    sessions.push_back(std::move(read.value));
  }
  const auto analysed = host::AnalyseStudy(std::move(sessions));
  if (!analysed.ok()) return Fail(what, analysed.status, analysed.message, kExitUsage);
  const host::StudyAnalysis& a = analysed.value;
  if (out.empty()) out = DefaultOut(a.study);

  std::error_code error;
  if (std::filesystem::exists(out, error) && !std::filesystem::is_directory(out, error))
    return Fail(what, protocol::Status::kInvalidArgument, out + ": not a directory", kExitUsage);
  std::filesystem::create_directories(out, error);
  if (error) {
    return Fail(what, protocol::Status::kIoError, out + ": cannot be created: " + error.message(),
                kExitFailed);
  }
  const auto written = host::WriteStudyReport(a, out);
  if (!written.ok()) return Fail(what, written.status, written.message, kExitFailed);
  const std::vector<std::string>& files = written.value;

  for (const std::string& note : a.notes)
    std::fprintf(stderr, "palpa study report: %s\n", note.c_str());
  if (JsonOutput()) {
    nlohmann::ordered_json j = {
        {"study", a.study}, {"sessions", a.sessions.size()}, {"files", files}, {"notes", a.notes}};
    if (a.comparison) {
      nlohmann::ordered_json metrics = nlohmann::ordered_json::array();
      for (const host::MetricComparison& m : a.comparison->metrics) {
        metrics.push_back({{"metric", m.metric},
                           {"sequential", m.sequential.value()},
                           {"simultaneous", m.simultaneous.value()},
                           {"combined_interval", m.by_own_n.combined},
                           {"significant", m.by_own_n.significant},
                           {"wilcoxon_p", m.participants.p}});
      }
      j["comparison"] = metrics;
    }
    PrintJson(j);
    return kExitOk;
  }
  std::printf("study %s: %zu sessions; %s/report.html and %zu CSV files\n", a.study.c_str(),
              a.sessions.size(), out.c_str(), files.size() - 1);
  if (a.comparison) {
    for (const host::MetricComparison& m : a.comparison->metrics) {
      std::printf("  %-3s sequential %s, simultaneous %s: %s\n", m.metric.c_str(),
                  host::ProportionText(m.sequential).c_str(),
                  host::ProportionText(m.simultaneous).c_str(),
                  m.by_own_n.significant ? "significant" : "not significant");
    }
  }
  return kExitOk;
}

}  // namespace palpa::cli
