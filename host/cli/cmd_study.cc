// palpa study: discrimination studies — each subcommand in a file of its own (cmd_study_*.cc).
#include "cli.h"

namespace palpa::cli {
namespace {

struct Subcommand {
  const char* name;
  int (*run)(Context&, const std::vector<std::string>&);
};

const Subcommand kSubcommands[] = {{"report", CmdStudyReport}};

int CmdStudy(Context& c, const std::vector<std::string>& args) {
  std::vector<std::string> names;
  for (const Subcommand& s : kSubcommands) names.push_back(s.name);
  if (args.empty()) return Usage("study", "a subcommand is missing: report");
  for (const Subcommand& s : kSubcommands) {
    if (args[0] == s.name) return s.run(c, {args.begin() + 1, args.end()});
  }
  const std::string near = Suggest(args[0], names);
  return Usage("study", "unknown subcommand '" + args[0] + "'" +
                            (near.empty() ? " (report)" : " (did you mean '" + near + "'?)"));
}

}  // namespace

const Command kStudyCommand{
    "study", "study report DIR... [--out OUT]",
    "report: analyses the sessions of one study (each DIR a session's directory: session.json\n"
    "and trials.jsonl) as the thesis analysed its studies, pooling the participants: Se, Sp,\n"
    "PPV and ACC per block, mode, condition and participant with Wilson intervals (each finger\n"
    "position of each non-practice detection trial counted once), the two modes compared by\n"
    "the combined interval, Wilcoxon on the participants and t-tests on trial times, staircase\n"
    "JNDs, and every session's provenance. Writes OUT/report.html (SVG charts, no scripts) and\n"
    "a CSV file per table; OUT (default STUDY-report) is created if missing. Sessions of\n"
    "different studies, or one participant twice, are refused. docs/studies.md.",
    CmdStudy};

}  // namespace palpa::cli
