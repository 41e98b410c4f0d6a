// Files written whole or not at all: new, replaced, and a failed write that leaves the old file
// and no temporary behind; never through a symlink planted beside the target, with the mode of
// the file replaced, and flushed to disk with the directory that names it.
#include "palpa/host/file_write.h"

#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "CppUTest/TestHarness.h"
#include "file_text.h"
#include "fsync_seam.h"

namespace fs = std::filesystem;
namespace ph = palpa::host;

TEST_GROUP(FileWrite) {
  fs::path dir;
  void setup() override {
    dir = MakeTestDir("palpa-write");
    CHECK(!dir.empty());
  }
  void teardown() override { RemoveTestDir(dir); }
  size_t Entries() const {
    return static_cast<size_t>(
        std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
  }
};

TEST(FileWrite, WritesANewFileAndReplacesAnOldOneWhole) {
  const fs::path file = dir / "out.bin";
  const std::string first("first\0with a zero byte", 22);
  CHECK(ph::WriteFileWhole(file.string(), first).ok());
  CHECK(palpa::testing::FileText(file) == first);
  const std::string second(100000, 'x');
  CHECK(ph::WriteFileWhole(file.string(), second).ok());
  CHECK(palpa::testing::FileText(file) == second);
  CHECK(ph::WriteFileWhole(file.string(), "").ok());
  LONGS_EQUAL(0, fs::file_size(file));
  LONGS_EQUAL(1, Entries());  // no temporary left beside it
}

TEST(FileWrite, AFailedWriteNamesTheFileAndLeavesNothing) {
  const fs::path missing = dir / "no-such-dir" / "out.svg";
  ph::Outcome written = ph::WriteFileWhole(missing.string(), "data");
  LONGS_EQUAL((int)palpa::protocol::Status::kIoError, (int)written.status);
  const std::string& error = written.message;
  CHECK(error.find(missing.string()) != std::string::npos);
  CHECK(error.find("No such file") != std::string::npos);
  // The target is a directory: refused, and nothing is left behind.
  const fs::path taken = dir / "taken";
  fs::create_directory(taken);
  fs::create_directory(taken / "inside");
  written = ph::WriteFileWhole(taken.string(), "data");
  CHECK_FALSE(written.ok());
  CHECK_TEXT(error.find("is a directory") != std::string::npos, error.c_str());
  CHECK(fs::is_directory(taken / "inside"));
  LONGS_EQUAL(1, Entries());
}

TEST(FileWrite, ASymlinkPlantedWhereTheTemporaryMightGoIsNeverFollowed) {
  // Whatever name a writer might pick beside the target, a link planted there to a victim file
  // must not redirect the write: the victim keeps its contents and the target gets the bytes.
  const fs::path victim = dir / "victim";
  std::ofstream(victim) << "precious";
  const fs::path out = dir / "out.pkg";
  for (const std::string& name : {"out.pkg.part" + std::to_string(getpid()),
                                  std::string("out.pkg.part"), std::string("out.pkg.tmp")}) {
    fs::create_symlink(victim, dir / name);
  }
  const ph::Outcome written = ph::WriteFileWhole(out.string(), "package");
  CHECK_TEXT(written.ok(), written.message.c_str());
  STRCMP_EQUAL("precious", palpa::testing::FileText(victim).c_str());
  STRCMP_EQUAL("package", palpa::testing::FileText(out).c_str());
  CHECK(fs::is_symlink(dir / "out.pkg.part"));  // planted links are left as they were
}

TEST(FileWrite, ASymlinkAtTheTargetIsRefusedNotFollowedOrReplaced) {
  const fs::path victim = dir / "victim";
  std::ofstream(victim) << "precious";
  const fs::path out = dir / "calibration.json";
  fs::create_symlink(victim, out);
  const ph::Outcome written = ph::WriteFileWhole(out.string(), "{}");
  CHECK_FALSE(written.ok());
  CHECK_TEXT(written.message.find("symbolic link") != std::string::npos, written.message.c_str());
  STRCMP_EQUAL("precious", palpa::testing::FileText(victim).c_str());
  CHECK(fs::is_symlink(out));
  LONGS_EQUAL(2, Entries());
}

TEST(FileWrite, TheReplacedFileKeepsItsMode) {
  const fs::path file = dir / "private.json";
  CHECK(ph::WriteFileWhole(file.string(), "one").ok());
  chmod(file.c_str(), 0600);
  CHECK(ph::WriteFileWhole(file.string(), "two").ok());
  LONGS_EQUAL(0600, fs::status(file).permissions() & fs::perms::all);
  chmod(file.c_str(), 0640);
  CHECK(ph::WriteFileWhole(file.string(), "three").ok());
  LONGS_EQUAL(0640, fs::status(file).permissions() & fs::perms::all);
  // A new file gets the usual mode for the process's umask.
  const mode_t mask = umask(022);
  const fs::path fresh = dir / "fresh.json";
  CHECK(ph::WriteFileWhole(fresh.string(), "new").ok());
  umask(mask);
  LONGS_EQUAL(0644, fs::status(fresh).permissions() & fs::perms::all);
}

TEST(FileWrite, TheFileAndThenItsDirectoryReachTheDisk) {
  g_record_fsyncs = true;
  CHECK(ph::WriteFileWhole((dir / "out.csv").string(), "data").ok());
  g_record_fsyncs = false;
  // The contents before the rename, the directory entry after it.
  CHECK_EQUAL(2u, g_fsync_count);
  CHECK_EQUAL('f', g_fsynced[0]);
  CHECK_EQUAL('d', g_fsynced[1]);
}
