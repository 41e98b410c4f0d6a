// Running the palpa command line (or any shell command) from a test: its exit code and everything
// it printed.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "CppUTest/TestHarness.h"

namespace palpa::testing {

/// A file's whole text ("" when it cannot be read).
inline std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Run {
  int code;
  std::string output;  ///< stdout and stderr
};

/// `command` through the shell: its exit code, and its stdout with its stderr (or without:
/// stderr goes to /dev/null).
inline Run Shell(const std::string& command, bool with_stderr = true) {
  FILE* p = popen((command + (with_stderr ? " 2>&1" : " 2>/dev/null")).c_str(), "r");
  std::string out;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), p)) > 0) out.append(buffer, n);
  const int status = pclose(p);
  return Run{WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// `palpa ARGS` through the shell, with `environment` (VAR=VALUE settings) for it. Each run has
/// no $PALPA_DEVICE and, unless `environment` gives one, a state directory with nothing in it: no
/// simulated board kept by another. The output is stdout and stderr, or stdout alone.
inline Run Palpa(const std::string& args, const std::string& environment = "",
                 bool with_stderr = true) {
  return Shell("env -u PALPA_DEVICE PALPA_STATE_DIR=/nonexistent-palpa-state " + environment + " " +
                   PALPA_CLI_PATH + " " + args,
               with_stderr);
}

inline bool Has(const Run& r, const std::string& text) {
  return r.output.find(text) != std::string::npos;
}

/// A refused command line: exit code 2 and the message naming what was wrong.
inline Run ExpectUsage(const std::string& args, const std::string& message) {
  const Run r = Palpa(args);
  LONGS_EQUAL_TEXT(2, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, message), r.output.c_str());
  return r;
}

/// A file name of this test process's own: two test runs at once must not share files.
inline std::string OwnTempPath(const std::string& name) {
  return "/tmp/palpa-cli-" + std::to_string(getpid()) + "-" + name;
}

}  // namespace palpa::testing
