// The claim a hosted board takes on what it drives: a lock file a neighbour planted, or a run
// directory others may write into, is refused before anything is written.
#include "process_claim.h"

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "CppUTest/TestHarness.h"
#include "file_text.h"
#include "temp_dir.h"

namespace hosted = palpa::hosted;

TEST_GROUP(ProcessClaim){};

TEST(ProcessClaim, ADirectoryOthersMayWriteIntoIsNotPrivate) {
  const std::string dir = palpa::testing::MakeTempDir("palpa-claim");
  const std::string run = dir + "/run";
  CHECK(hosted::PrivateDirectory(run));  // made, this user's, closed to others
  chmod(run.c_str(), 0777);
  CHECK(!hosted::PrivateDirectory(run));
  chmod(run.c_str(), 0700);
  CHECK(hosted::PrivateDirectory(run));
  const std::string link = dir + "/link";
  CHECK(symlink(run.c_str(), link.c_str()) == 0);
  CHECK(!hosted::PrivateDirectory(link));  // a link, even to a private directory
}

TEST(ProcessClaim, ALockFileThatIsALinkIsRefusedAndItsTargetUntouched) {
  const std::string dir = palpa::testing::MakeTempDir("palpa-claim");
  const std::string victim = dir + "/victim";
  std::ofstream(victim) << "precious contents\n";
  const std::string lock = dir + "/module.lock";
  CHECK(symlink(victim.c_str(), lock.c_str()) == 0);
  hosted::ProcessClaim claim;
  std::string error;
  CHECK(!claim.Take(lock, "analog_module tcp:h:502 unit 1", &error));
  CHECK_TEXT(error.find(lock) != std::string::npos, error.c_str());
  STRCMP_EQUAL("precious contents\n", palpa::testing::FileText(victim).c_str());
}

TEST(ProcessClaim, AHeldClaimIsRefusedNamingItsHolder) {
  const std::string lock = palpa::testing::MakeTempDir("palpa-claim") + "/module.lock";
  hosted::ProcessClaim first, second;
  std::string error;
  CHECK_TEXT(first.Take(lock, "analog_module m", &error), error.c_str());
  STRCMP_EQUAL(std::to_string(getpid()).c_str(), palpa::testing::FileText(lock).c_str());
  CHECK(!second.Take(lock, "analog_module m", &error));
  CHECK_TEXT(error.find("in use by process " + std::to_string(getpid())) != std::string::npos,
             error.c_str());
  first.Release();
  CHECK_TEXT(second.Take(lock, "analog_module m", &error), error.c_str());
}

TEST(ProcessClaim, ALockFileOfAnotherUserIsRefused) {
  // Only root can give a file away; the test run (./run test) is root's.
  CHECK_TEXT(geteuid() == 0, "this test gives a file to another user: run it as root");
  const std::string lock = palpa::testing::MakeTempDir("palpa-claim") + "/module.lock";
  std::ofstream(lock) << "4242";
  CHECK(chown(lock.c_str(), 65534, 65534) == 0);
  hosted::ProcessClaim claim;
  std::string error;
  CHECK(!claim.Take(lock, "analog_module m", &error));
  CHECK_TEXT(error.find("not a file of this user") != std::string::npos, error.c_str());
  STRCMP_EQUAL("4242", palpa::testing::FileText(lock).c_str());
}
