// palpa sim: without a kept board each command runs on a throwaway one and says so; a kept board
// lives across commands, and its flash (configuration, firmware slots) across restarts.
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixtures.h"

using palpa::testing::Has;
using palpa::testing::kDevelopmentKey;
using palpa::testing::MakeTempDir;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP(CliSim) {
  std::string state, env;
  void setup() override {
    state = MakeTempDir("palpa-cli-state");
    env = "PALPA_STATE_DIR=" + state + " ";
  }
  void teardown() override {
    Palpa("sim stop", env);
    std::filesystem::remove_all(state);
  }
};

TEST(CliSim, WithoutAKeptBoardEachCommandSaysItRanOnAThrowawayOne) {
  Run r = Palpa("estop", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "this ran on a throwaway simulated board (sim:thesis-5finger)"),
             r.output.c_str());
  CHECK(Has(r, "'palpa sim start' keeps one board running"));
  r = Palpa("clear", env);  // another board: nothing to clear, and it says so
  CHECK_TEXT(Has(r, "no faults were latched"), r.output.c_str());
  CHECK(Has(r, "throwaway"));
  r = Palpa("sim status", env);
  CHECK(Has(r, "no simulated board is running"));
}

TEST(CliSim, AKeptBoardLivesAcrossCommandsAndItsFlashAcrossRestarts) {
  Run r = Palpa("sim start", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "simulated thesis-5finger board running"));
  r = Palpa("sim start", env);  // one at a time
  LONGS_EQUAL(1, r.code);
  CHECK(Has(r, "already running"));
  // estop then clear: the same board, so the clear finds the EStop latched.
  r = Palpa("estop", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_FALSE(Has(r, "throwaway"));
  r = Palpa("clear", env);
  CHECK_TEXT(Has(r, "faults cleared: estop_command"), r.output.c_str());
  // A configuration set in one command is there in the next, and once saved after a restart.
  LONGS_EQUAL(0, Palpa("config set board.host_timeout_us=200000", env).code);
  r = Palpa("--json config show", env);
  LONGS_EQUAL(200000, nlohmann::json::parse(r.output)["board"]["host_timeout_us"].get<int>());
  r = Palpa("config save", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = Palpa("sim stop", env);
  CHECK_TEXT(Has(r, "its flash stays in " + state + "/sim-thesis-5finger.flash"), r.output.c_str());
  LONGS_EQUAL(0, Palpa("sim start", env).code);
  r = Palpa("info", env);
  CHECK_TEXT(Has(r, "configuration thesis-5finger (saved)"), r.output.c_str());
  r = Palpa("--json config show", env);
  LONGS_EQUAL(200000, nlohmann::json::parse(r.output)["board"]["host_timeout_us"].get<int>());
  r = Palpa("--json sim status", env);
  const auto status = nlohmann::json::parse(r.output);
  CHECK(status["running"].get<bool>());
  STRCMP_EQUAL("thesis-5finger", status["config"].get<std::string>().c_str());

  // The firmware slots and boot state are in the same flash: an update survives a restart.
  std::ofstream(state + "/a.bin") << std::string(20000, 'a');
  std::ofstream(state + "/b.bin") << std::string(20000, 'b');
  r = Palpa("package " + state + "/a.bin " + state + "/b.bin --version 0.3.0 --counter 2 --sign " +
                kDevelopmentKey + " --out " + state + "/new.palpa",
            env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = Palpa("flash " + state + "/new.palpa", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  LONGS_EQUAL(0, Palpa("sim stop", env).code);
  LONGS_EQUAL(0, Palpa("sim start", env).code);
  r = Palpa("info", env);
  CHECK_TEXT(Has(r, "firmware      0.3.0"), r.output.c_str());
  CHECK(Has(r, "image slot    1, anti-rollback counter 2"));

  // A flash file belongs to one configuration.
  LONGS_EQUAL(0, Palpa("sim stop", env).code);
  r = Palpa("sim start --config thesis-pneumatic-3 --flash " + state + "/sim-thesis-5finger.flash",
            env);
  LONGS_EQUAL(1, r.code);
  CHECK_TEXT(Has(r, "the flash of a thesis-5finger board, not of a thesis-pneumatic-3 one"),
             r.output.c_str());
  r = Palpa("sim stop", env);
  CHECK(Has(r, "no simulated board is running"));
}

TEST(CliSim, ARecordWhoseBoardIsGoneIsNotUsed) {
  LONGS_EQUAL(0, Palpa("sim start", env).code);
  const auto status = nlohmann::json::parse(Palpa("--json sim status", env).output);
  kill(status["pid"].get<int>(), SIGKILL);
  for (int i = 0; i < 100 && kill(status["pid"].get<int>(), 0) == 0; ++i) usleep(20000);
  const Run r = Palpa("info", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "no longer running"));
  CHECK(Has(r, "throwaway"));
}
