// The test harness's child process: its output is read for its whole life, so a child that writes
// more than a pipe holds after announcing itself runs on and exits.
#include <unistd.h>

#include <string>

#include "sim_process.h"

#include "CppUTest/TestHarness.h"

TEST_GROUP(SimProcessOutput){};

TEST(SimProcessOutput, AChildThatWritesMoreThanThePipeHoldsRunsOnAndExits) {
  palpa::testing::SimProcess child;
  // 1 MiB to stderr after the announcement: sixteen times a pipe's default capacity.
  CHECK_TEXT(child.Start({"-c",
                          "echo 'listening on tcp:127.0.0.1:1'; "
                          "head -c 1048576 /dev/zero | tr '\\0' x >&2; echo the-end >&2"},
                         "/bin/sh"),
             child.output().c_str());
  LONGS_EQUAL(0, child.WaitExit(5000));
  // Kept for a failure's message: the tail, bounded (read once the reader reached the end).
  const std::string later = [&] {
    for (int i = 0; i < 250; ++i) {
      const std::string text = child.later_output();
      if (text.find("the-end") != std::string::npos) return text;
      usleep(20000);
    }
    return child.later_output();
  }();
  CHECK_TEXT(later.size() <= 64 * 1024, std::to_string(later.size()).c_str());
  CHECK(later.size() > 60 * 1024);
  CHECK(later.find_first_not_of('x') == later.size() - 8);
  STRCMP_EQUAL("the-end\n", later.substr(later.size() - 8).c_str());
}
