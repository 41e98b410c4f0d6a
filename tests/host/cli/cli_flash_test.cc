// palpa package, flash and keygen: packages made, signed, checked and flashed over the link to
// palpa-sim; counter jumps, downgrades and keys the board does not trust refused.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixtures.h"

using palpa::testing::ExpectUsage;
using palpa::testing::FileText;
using palpa::testing::Has;
using palpa::testing::kDevelopmentKey;
using palpa::testing::kNowhere;
using palpa::testing::MakeTempDir;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP(CliFlash){};

TEST(CliFlash, PackagesAreMadeCheckedAndFlashedOverTheLink) {
  const std::string dir = MakeTempDir("palpa-flash-cli");
  std::ofstream(dir + "/a.bin") << std::string(20000, 'a');
  std::ofstream(dir + "/b.bin") << std::string(20000, 'b');
  const auto package = [&](const std::string& version, const std::string& counter,
                           const std::string& key, const std::string& name) {
    return Palpa("package " + dir + "/a.bin " + dir + "/b.bin --version " + version +
                 " --counter " + counter + " --sign " + key + " --out " + dir + "/" + name);
  };
  Run r = package("0.3.0", "2", kDevelopmentKey, "new.palpa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "signed by key "), r.output.c_str());
  LONGS_EQUAL(0, package("0.0.9", "0", kDevelopmentKey, "old.palpa").code);
  LONGS_EQUAL(0, package("0.2.0", "2", kDevelopmentKey, "down.palpa").code);
  // The review's attack: a package that would pin the board's counter at its maximum.
  LONGS_EQUAL(0, package("9.9.9", "4294967295", kDevelopmentKey, "pin.palpa").code);
  // Signed by a key of this lab's own, which the development board does not trust.
  const std::string lab = dir + "/lab.key";
  r = Palpa("keygen " + lab);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  LONGS_EQUAL(0, package("0.4.0", "2", lab, "lab.palpa").code);
  std::ofstream(dir + "/lab.key.pub2") << "# not a key\nhello\n";
  r = ExpectUsage("package " + dir + "/a.bin " + dir + "/b.bin --version 1.0.0 --counter 1 --out " +
                      dir + "/unsigned.palpa",
                  "--sign KEY");
  r = ExpectUsage("package " + dir + "/a.bin " + dir +
                      "/b.bin --version 1.0.0 --counter 1 --sign " + dir + "/lab.key.pub2 --out " +
                      dir + "/x.palpa",
                  "not a private key file");
  // Bad command lines and bad packages are named before anything is sent.
  r = ExpectUsage(kNowhere + "flash", "needs a PACKAGE");
  r = ExpectUsage(kNowhere + "flash " + dir + "/missing.palpa", "cannot be read");
  std::ofstream(dir + "/text.palpa") << "hello";
  r = ExpectUsage(kNowhere + "flash " + dir + "/text.palpa", "not a palpa update package");
  {
    const std::string bytes = FileText(dir + "/new.palpa");
    std::ofstream(dir + "/cut.palpa", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  r = ExpectUsage(kNowhere + "flash " + dir + "/cut.palpa", "truncated");
  r = ExpectUsage(kNowhere + "flash " + dir + "/new.palpa --reset-line gpiochip9:1",
                  "--reset-line 'gpiochip9:1': no GPIO chip");
  r = Palpa("package " + dir + "/a.bin --version 1 --counter 1 --out x");
  LONGS_EQUAL(2, r.code);

  palpa::testing::SimProcess sim;
  CHECK(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0"}));
  const std::string device = "--device " + sim.address() + " ";
  r = Palpa(device + "flash " + dir + "/new.palpa --dry-run");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "would write 0.3.0"));
  CHECK_TEXT(Has(r, "anti-rollback counter 2 (board's floor 1), signed by key "), r.output.c_str());
  // The counter jump is flagged before anything is written (the dry run says so too).
  r = ExpectUsage(device + "flash " + dir + "/pin.palpa --dry-run", "jumps from the board's 1");
  r = ExpectUsage(device + "flash " + dir + "/pin.palpa", "--allow-counter-jump");
  CHECK(Has(r, "Nothing was written"));
  // The board itself refuses an image its keys did not sign, at activation.
  r = Palpa(device + "flash " + dir + "/lab.palpa");
  LONGS_EQUAL_TEXT(2, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "signed by a key this board does not trust"), r.output.c_str());
  r = Palpa(device + "flash " + dir + "/new.palpa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "updated 0.1.0 → 0.3.0 (slot 1), confirmed"));
  // Its stderr is a pipe here, as in a log: the bar is a line a tenth of the way (100 redraws
  // joined by carriage returns on a terminal).
  CHECK_TEXT(r.output.find('\r') == std::string::npos, r.output.c_str());
  CHECK_TEXT(Has(r, "] 100 %  "), r.output.c_str());
  size_t bars = 0;
  for (size_t at = r.output.find("] "); at != std::string::npos; at = r.output.find("] ", at + 1))
    bars += r.output.compare(at + 5, 3, " % ") == 0;
  CHECK_TEXT(bars >= 2 && bars <= 11, r.output.c_str());
  r = Palpa(device + "info");
  CHECK(Has(r, "firmware      0.3.0"));
  CHECK(Has(r, "image slot    1, anti-rollback counter 2"));
  r = ExpectUsage(device + "flash " + dir + "/old.palpa",
                  "anti-rollback counter 0 is below the board's 2");
  // A lower version at the same counter: only when asked for.
  r = ExpectUsage(device + "flash " + dir + "/down.palpa",
                  "0.2.0 is older than the running 0.3.0 at the same anti-rollback counter 2");
  r = Palpa(device + "flash " + dir + "/down.palpa --allow-downgrade");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "updated 0.3.0 → 0.2.0 (slot 0), confirmed"));
}

TEST(CliFlash, KeygenWritesAPrivateKeyOnlyItsOwnerReadsAndNeverOverwrites) {
  const std::string dir = MakeTempDir("palpa-keygen");
  const std::string key = dir + "/release.key";
  Run r = Palpa("keygen " + key);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "(mode 0600: keep it secret)"), r.output.c_str());
  struct stat st {};
  LONGS_EQUAL(0, stat(key.c_str(), &st));
  LONGS_EQUAL(0600, st.st_mode & 0777);
  const std::string before = FileText(key);
  r = ExpectUsage("keygen " + key, "exists; not overwritten");
  CHECK(FileText(key) == before);
  r = Palpa("--json keygen " + dir + "/second.key");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const auto json = nlohmann::json::parse(r.output);
  LONGS_EQUAL(16, json["key_id"].get<std::string>().size());
  r = ExpectUsage("keygen", "needs one FILE");
  std::filesystem::remove_all(dir);
}
