// Temporaries of killed writers: the next writer of the same file removes them, never one whose
// writer is alive (another process, holding it open), nor anything that only looks like one.
#include "palpa/hal/linux/atomic_file.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "CppUTest/TestHarness.h"
#include "file_text.h"
#include "fsync_seam.h"

namespace fs = std::filesystem;
using palpa::hal::linux_files::AtomicFile;
using palpa::hal::linux_files::WriteFileWhole;

TEST_GROUP(StaleTemporaries) {
  fs::path dir, out;
  void setup() override {
    dir = MakeTestDir("palpa-atomic");
    CHECK(!dir.empty());
    out = dir / "stamps.json";
  }
  void teardown() override { RemoveTestDir(dir); }
  /// The temporaries of `out` in the directory: ".stamps.json.XXXXXX.part".
  int Temporaries() const {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string name = e.path().filename().string();
      n += name.rfind(".stamps.json.", 0) == 0 && name.size() == 24 && name.substr(19) == ".part" &&
           !fs::is_symlink(e.path());
    }
    return n;
  }
};

TEST(StaleTemporaries, AKilledWritersTemporaryIsRemovedByTheNextWriter) {
  const pid_t child = fork();
  if (child == 0) {
    AtomicFile f;
    if (f.Open(out.string()).ok()) f.Write("half of it");
    raise(SIGKILL);  // as palpa-sim killed mid-run: no destructor, no Abandon
  }
  int status = 0;
  waitpid(child, &status, 0);
  CHECK(WIFSIGNALED(status));
  LONGS_EQUAL(1, Temporaries());  // what the kill left
  const auto written = WriteFileWhole(out.string(), "whole");
  CHECK_TEXT(written.ok(), written.message.c_str());
  LONGS_EQUAL(0, Temporaries());
  STRCMP_EQUAL("whole", palpa::testing::FileText(out).c_str());
}

TEST(StaleTemporaries, ALiveWritersTemporaryInAnotherProcessIsKept) {
  int ready[2], go[2];
  CHECK(pipe(ready) == 0 && pipe(go) == 0);
  const pid_t child = fork();
  if (child == 0) {
    close(ready[0]);  // a parent that ends early then ends the child's wait
    close(go[1]);
    AtomicFile f;
    const bool opened = f.Open(out.string()).ok();
    f.Write("the child's");
    char c = 'r';
    if (write(ready[1], &c, 1) != 1 || read(go[0], &c, 1) != 1) _exit(2);
    _exit(opened && f.Commit().ok() ? 0 : 1);  // its temporary must still be there to rename
  }
  close(ready[1]);  // a child that ends early then ends the read
  close(go[0]);
  char c = 0;
  CHECK(read(ready[0], &c, 1) == 1);
  LONGS_EQUAL(1, Temporaries());
  const auto written = WriteFileWhole(out.string(), "the parent's");
  CHECK_TEXT(written.ok(), written.message.c_str());
  LONGS_EQUAL(1, Temporaries());  // the child's, untouched
  CHECK(write(go[1], &c, 1) == 1);
  int status = 0;
  waitpid(child, &status, 0);
  close(ready[0]);
  close(go[1]);
  CHECK(WIFEXITED(status));
  LONGS_EQUAL(0, WEXITSTATUS(status));
  STRCMP_EQUAL("the child's", palpa::testing::FileText(out).c_str());
  LONGS_EQUAL(0, Temporaries());
}

TEST(StaleTemporaries, OnlyExactlyThatNameShapeIsRemovedAndNeverALink) {
  const fs::path victim = dir / "victim";
  std::ofstream(victim) << "precious";
  fs::create_symlink(victim, dir / ".stamps.json.abcdef.part");
  for (const char* name :
       {".stamps.json.abc.part", ".stamps.json.abcde!.part", ".other.json.abcdef.part",
        ".stamps.json.abcdef.tmp", "stamps.json.abcdef.part", ".stamps.json.abcdef.part.keep"}) {
    std::ofstream(dir / name) << "not a temporary of stamps.json";
  }
  std::ofstream(dir / ".stamps.json.zyxwvu.part") << "a killed writer's";
  const auto written = WriteFileWhole(out.string(), "new");
  CHECK_TEXT(written.ok(), written.message.c_str());
  CHECK_FALSE(fs::exists(dir / ".stamps.json.zyxwvu.part"));
  CHECK(fs::is_symlink(dir / ".stamps.json.abcdef.part"));
  STRCMP_EQUAL("precious", palpa::testing::FileText(victim).c_str());
  LONGS_EQUAL(9, std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}
