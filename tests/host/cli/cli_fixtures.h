// What the palpa command-line tests share: a device that is never there, scratch directories, a
// simulated board for a test group, the development signing key.
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <string>
#include <system_error>

#include "cli_run.h"
#include "file_text.h"
#include "sim_process.h"
#include "temp_dir.h"

#include "CppUTest/TestHarness.h"

namespace palpa::testing {

/// A device nothing listens on: a command line refused as a usage error never tries to open it.
inline const std::string kNowhere = "--device tcp:127.0.0.1:1 ";

inline const std::string kDevelopmentKey = PALPA_DEVELOPMENT_KEY;  // DEVELOPMENT ONLY

/// A test group's board (TEST_GROUP_BASE): palpa-sim with thesis-5finger on a TCP port, `device`
/// the option that names it, and `dir`, a scratch directory; both go when each test ends.
struct SimBoardGroup : Utest {
  SimProcess sim;
  std::string device;
  std::string dir;
  void setup() override {
    dir = MakeTempDir("palpa-cli-board");
    CHECK(sim.Start({"--config", "thesis-5finger", "--listen", "tcp:127.0.0.1:0"}));
    device = "--device " + sim.address() + " ";
  }
  void teardown() override {
    sim.Stop();
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

}  // namespace palpa::testing
