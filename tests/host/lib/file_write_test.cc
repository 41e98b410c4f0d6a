// Files written whole or not at all: new, replaced, and a failed write that leaves the old file
// and no temporary behind.
#include "palpa/host/file_write.h"

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "CppUTest/TestHarness.h"

namespace fs = std::filesystem;
namespace ph = palpa::host;

namespace {

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_GROUP(FileWrite) {
  fs::path dir;
  void setup() override {
    std::string pattern = (fs::temp_directory_path() / "palpa-write-XXXXXX").string();
    CHECK(mkdtemp(pattern.data()) != nullptr);
    dir = pattern;
  }
  void teardown() override { fs::remove_all(dir); }
  size_t Entries() const {
    return static_cast<size_t>(
        std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
  }
};

TEST(FileWrite, WritesANewFileAndReplacesAnOldOneWhole) {
  const fs::path file = dir / "out.bin";
  const std::string first("first\0with a zero byte", 22);
  CHECK(ph::WriteFileWhole(file.string(), first));
  CHECK(ReadAll(file) == first);
  const std::string second(100000, 'x');
  CHECK(ph::WriteFileWhole(file.string(), second));
  CHECK(ReadAll(file) == second);
  CHECK(ph::WriteFileWhole(file.string(), ""));
  LONGS_EQUAL(0, fs::file_size(file));
  LONGS_EQUAL(1, Entries());  // no temporary left beside it
}

TEST(FileWrite, AFailedWriteNamesTheFileAndLeavesNothing) {
  std::string error;
  const fs::path missing = dir / "no-such-dir" / "out.svg";
  CHECK_FALSE(ph::WriteFileWhole(missing.string(), "data", &error));
  CHECK(error.find(missing.string()) != std::string::npos);
  CHECK(error.find("No such file") != std::string::npos);
  // The target is a directory: the temporary is written, the rename fails, and is cleaned up.
  const fs::path taken = dir / "taken";
  fs::create_directory(taken);
  fs::create_directory(taken / "inside");  // not empty: rename cannot replace it
  CHECK_FALSE(ph::WriteFileWhole(taken.string(), "data", &error));
  CHECK(error.find("cannot replace") != std::string::npos);
  CHECK(fs::is_directory(taken / "inside"));
  LONGS_EQUAL(1, Entries());
}
