// Files and values that try to hurt the host library: a FIFO or a device named like a calibration,
// files far larger or deeper than any real one, numbers JSON cannot hold, NaN targets, and a
// calibration that exists but is invalid — each refused with what and where, never waited on,
// crashed on or silently replaced by a fallback.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <thread>

#include "example_calibration.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/device.h"
#include "palpa/host/stiffness_map.h"
#include "palpa/host/stimulus_set.h"

#include "CppUTest/TestHarness.h"
#include "temp_dir.h"
#include "text_checks.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

using palpa::testing::Contains;

/// Why `r` was refused, or "" when it was not.
template <class R>
std::string MessageIfRefused(const R& r) {
  return r.ok() ? "" : r.message;
}

std::string ValidText() {
  return ph::SerializeCalibration(palpa::testing::ExampleCalibration()).value;
}

/// `text` with the first `from` replaced by `to`.
std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  CHECK_TEXT(at != std::string::npos, from.c_str());
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST_GROUP(HostileFiles) {
  std::string dir;
  void setup() override { dir = palpa::testing::MakeTempDir("palpa-hostile"); }
  void teardown() override { std::system(("rm -rf " + dir).c_str()); }
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = dir + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
};

TEST(HostileFiles, AFifoNamedLikeACalibrationIsRefusedNotWaitedOn) {
  const std::string path = dir + "/PN-1.json";
  CHECK(mkfifo(path.c_str(), 0600) == 0);
  // Were the reader to open the FIFO and wait for a writer, this one lets it go after a while
  // (so the test fails rather than hangs).
  std::thread writer([&path] {
    for (int i = 0; i < 300; ++i) {
      const int fd = open(path.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) {
        close(fd);
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  const auto c = ph::LoadCalibration(path);
  writer.join();
  CHECK_FALSE(c.ok());
  std::string error = c.message;
  CHECK_TEXT(Contains(error, path + ": not a regular file"), error.c_str());
  error = MessageIfRefused(ph::LoadCalibration("/dev/null"));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, "/dev/null: not a regular file"), error.c_str());
}

TEST(HostileFiles, AFileLargerThanItsKindAllowsIsRefusedNamingTheLimit) {
  // A valid calibration padded far beyond any real one: refused before it is read into memory.
  const std::string path = Write("PN-1.json", ValidText() + std::string(3 << 20, ' '));
  std::string error;
  error = MessageIfRefused(ph::LoadCalibration(path));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, path + ": larger than the"), error.c_str());
  CHECK_TEXT(Contains(error, "limit for a calibration file"), error.c_str());
  // A stimulus set likewise, and one that is a device is never read from.
  const std::string set =
      Write("set.json", ph::ShippedStimulusSetText("thesis-jamming-8") + std::string(1 << 20, ' '));
  error = MessageIfRefused(ph::LoadStimulusSet(set));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, set + ": larger than the 256 KiB limit for a stimulus set"),
             error.c_str());
  error = MessageIfRefused(ph::LoadStimulusSet("/dev/zero"));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, "/dev/zero: not a regular file"), error.c_str());
}

TEST(HostileFiles, DeepNestingIsRefusedNamingTheLimit) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  std::string error;
  error = MessageIfRefused(ph::ParseCalibration(deep));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, "nested deeper than"), error.c_str());
  // Within a level file's size limit, nesting alone is refused.
  const std::string path = Write(
      "levels.json", "{\"pneumatic\": " + std::string(20000, '[') + std::string(20000, ']') + "}");
  error = MessageIfRefused(ph::LevelTables::Load(path));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, path + ": pneumatic"), error.c_str());
  CHECK_TEXT(Contains(error, "nested deeper than"), error.c_str());
}

TEST(HostileFiles, NumbersJsonCannotHoldAreNamedByTheirField) {
  std::string error = MessageIfRefused(ph::ParseCalibration(
      Replaced(ValidText(), "\"speed_um_s\": 100.0", "\"speed_um_s\": 1e400")));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, "conditions.speed_um_s: "), error.c_str());
  CHECK_TEXT(Contains(error, "1e400"), error.c_str());
  CHECK_FALSE(Contains(error, "[json.exception"));  // words for people, not the library's codes
  const std::string curve = Replaced(ValidText(), "\"output\": 300.0", "\"output\": -1e999");
  error = MessageIfRefused(ph::ParseCalibration(curve));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, "curve[1].output: "), error.c_str());
}

TEST(HostileFiles, LevelFilesNameTheFieldOfEveryMistake) {
  std::string error;
  std::string path =
      Write("levels.json",
            "{\"pneumatic\": {\"levels_kpa\": \"high\"}, \"jamming\": {\"bias_kpa\": "
            "20, \"levels_kpa\": [0]}}");
  error = MessageIfRefused(ph::LevelTables::Load(path));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, path + ": pneumatic.levels_kpa: must be an array"), error.c_str());
  path = Write("levels.json",
               "{\"pneumatic\": {\"levels_kpa\": [0, 10]}, \"jamming\": {\"bias_kpa\": 1e400, "
               "\"levels_kpa\": [0]}}");
  error = MessageIfRefused(ph::LevelTables::Load(path));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, path + ": jamming.bias_kpa: "), error.c_str());
  path = Write("levels.json", "{\"pneumatic\": {\"levels_kpa\": [0, 10]}}");
  error = MessageIfRefused(ph::LevelTables::Load(path));
  CHECK_FALSE(error.empty());
  CHECK_TEXT(Contains(error, path + ": jamming: missing"), error.c_str());
}

TEST_GROUP(HostileValues) {
  pp::FingerSummary pneumatic{pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, 0, pp::kNoLine};
  pp::FingerSummary jamming{pp::FingerKind::kJamming, pp::FingerMode::kTarget, 3, 5};
  ph::LevelTables levels = ph::LevelTables::Shipped();
  ph::FingerCurves curves;
};

TEST(HostileValues, NotANumberIsRefusedUnderEveryPolicy) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (ph::RangePolicy policy : {ph::RangePolicy::kRefuse, ph::RangePolicy::kClamp}) {
    for (double bad : {nan, inf, -inf}) {
      for (ph::TargetKind kind : {ph::TargetKind::kNormalized, ph::TargetKind::kDeformationMm,
                                  ph::TargetKind::kPressureKpa, ph::TargetKind::kLevel}) {
        const ph::Mapped m = ph::MapRequest(pneumatic, levels, curves, {kind, bad}, policy);
        CHECK_TEXT(m.status != pp::Status::kOk, m.note.c_str());
        CHECK_TEXT(Contains(m.error, "not a finite number"), m.error.c_str());
      }
      const ph::Mapped m =
          ph::MapRequest(jamming, levels, curves, {ph::TargetKind::kStiffnessNPerMm, bad}, policy);
      CHECK_TEXT(m.status != pp::Status::kOk, m.note.c_str());
    }
  }
}

TEST_GROUP(HostileCalibrations) {
  std::string dir;
  void setup() override { dir = palpa::testing::MakeTempDir("palpa-hostile"); }
  void teardown() override { std::system(("rm -rf " + dir).c_str()); }
  std::unique_ptr<ph::Device> Open(bool strict) {
    ph::DeviceOptions options;
    options.calibration_dir = dir;
    options.invalid_calibration_is_error = strict;
    auto opened = ph::Device::Open("sim:thesis-5finger", options);
    CHECK_TEXT(opened.ok(), opened.message.c_str());
    return std::move(opened.value);
  }
};

TEST(HostileCalibrations, AnInvalidCalibrationIsNamedWithItsReasonOrRefusedWhenAsked) {
  // PN-1's file exists but a field is out of range: the fallback to the nominal curves says why.
  const std::string path = dir + "/PN-1.json";
  std::ofstream(path) << Replaced(ValidText(), "\"speed_um_s\": 100.0", "\"speed_um_s\": 99000");
  auto d = Open(false);
  ph::Outcome o = d->Set({{0, {ph::TargetKind::kLevel, 1}}});
  CHECK_TEXT(o.ok(), o.message.c_str());
  CHECK_TEXT(Contains(o.notes[0], "nominal thesis curves"), o.notes[0].c_str());
  CHECK_TEXT(Contains(o.notes[0], path + ": conditions.speed_um_s: 99000 is outside"),
             o.notes[0].c_str());
  // A finger without a file is no error either way.
  o = d->Set({{1, {ph::TargetKind::kLevel, 1}}});
  CHECK_TEXT(Contains(o.notes[0], "no calibration for PN-2"), o.notes[0].c_str());
  d.reset();
  d = Open(true);
  o = d->Set({{1, {ph::TargetKind::kLevel, 1}}, {0, {ph::TargetKind::kLevel, 1}}});
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)o.status);
  // Named as the caller numbers fingers: this API from 0.
  CHECK_TEXT(Contains(o.message, "finger 0: " + path + ": conditions.speed_um_s"),
             o.message.c_str());
  CHECK(d->Set({{1, {ph::TargetKind::kLevel, 1}}}).ok());
}

TEST(HostileCalibrations, RawSetpointsThatAreNotNumbersAreRefused) {
  auto d = Open(false);
  const ph::Outcome o = d->SetLines({{0, std::numeric_limits<double>::quiet_NaN()}});
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)o.status);
  CHECK_TEXT(Contains(o.message, "line 0: nan kPa is not a finite number"), o.message.c_str());
}
