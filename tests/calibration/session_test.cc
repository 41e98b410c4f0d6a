// calibration::Session on the in-process simulated rig (virtual time, so a seeded run is the same
// every time): its files are byte for byte what the protocol's run gives when written as palpa
// calibrate wrote them before the session existed; each phase's failure carries its status (a
// safety limit told apart from a lost device by its code); a stopped session keeps its journal and
// a second one resumes it.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "palpa/calibration/report.h"
#include "palpa/calibration/session.h"
#include "palpa/host/file_write.h"
#include "short_protocol.h"
#include "sim_rig.h"
#include "temp_dir.h"

// Last: its memory-leak macros redefine new.
#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace pt = palpa::testing;
namespace pp = palpa::protocol;
namespace ph = palpa::host;

namespace {

constexpr const char* kDate = "2026-11-22T12:00:00Z";

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool Exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

cal::SessionOptions Options(const std::string& dir) {
  cal::SessionOptions o;
  o.finger = 0;
  o.protocol = pt::ShortProtocol();
  o.out_dir = dir;
  o.date = kDate;
  return o;
}

}  // namespace

TEST_GROUP(CalibrationSession){};

TEST(CalibrationSession, ItsFilesAreTheProtocolsRunByteForByte) {
  // The reference: the protocol run directly and its results written as palpa calibrate wrote
  // them (raw readings a line each, the calibration file, the report).
  std::string csv, json, html;
  {
    pt::SimRig sim({"thesis-5finger", 0, 0, 31});
    cal::Rig rig = sim.rig();
    cal::Journal journal;
    cal::CalibrationRun run;
    const cal::RunInfo info{"PN-1", 7, kDate, "sim", "PN-1.csv"};
    const cal::RigStatus s =
        cal::RunCalibration(rig, 0, pt::ShortProtocol(), info, journal, nullptr, &run);
    CHECK_TEXT(s.ok(), s.message.c_str());
    for (const std::string& row : run.csv) csv += row + "\n";
    const auto text = ph::SerializeCalibration(run.file);
    CHECK_TEXT(text.ok(), text.message.c_str());
    json = text.value;
    html = cal::RenderReport(run);
  }
  const std::string dir = pt::MakeTempDir("palpa-session") + "/out";  // made by the session
  pt::SimRig sim({"thesis-5finger", 0, 0, 31});
  cal::Session session(sim.rig(), "PN-1", 7, false, Options(dir));
  const ph::Outcome o = session.Calibrate(nullptr);
  CHECK_TEXT(o.ok(), o.message.c_str());
  CHECK(session.files() ==
        std::vector<std::string>({dir + "/PN-1.json", dir + "/PN-1.csv", dir + "/PN-1.html"}));
  CHECK(ReadAll(dir + "/PN-1.csv") == csv);
  CHECK(ReadAll(dir + "/PN-1.json") == json);
  CHECK(ReadAll(dir + "/PN-1.html") == html);
  CHECK_FALSE(Exists(dir + "/PN-1.journal.json"));  // a finished run leaves no journal
  const auto summary = session.Summary(false, 1);
  STRCMP_EQUAL("PN-1", summary["calibrated"].get<std::string>().c_str());
  LONGS_EQUAL(1, summary["finger"].get<int>());
  STRCMP_EQUAL(ph::CompensatorLabel(session.result().file).c_str(),
               summary["compensator"].get<std::string>().c_str());
}

TEST(CalibrationSession, EachPhaseSaysWhatFailedWithItsStatus) {
  pt::SimRig sim({"thesis-5finger", 0, 0, 32});
  const std::string dir = pt::MakeTempDir("palpa-session");
  {
    cal::Session session(sim.rig(), "PN-1", 7, false, Options(dir));
    const ph::Outcome o = session.Resume();
    LONGS_EQUAL((int)pp::Status::kNotFound, (int)o.status);
    STRCMP_CONTAINS("no journal", o.message.c_str());
  }
  {
    CHECK(ph::WriteFileWhole(dir + "/PN-1.journal.json", "{\"sweep\": 3}").ok());
    cal::Session session(sim.rig(), "PN-1", 7, false, Options(dir));
    LONGS_EQUAL((int)pp::Status::kBadValue, (int)session.Resume().status);
  }
  {
    CHECK(ph::WriteFileWhole(dir + "/PN-1.json", "{}").ok());
    cal::Session session(sim.rig(), "PN-1", 7, false, Options(dir));
    const ph::Outcome o = session.LoadPrevious();  // OUT/SERIAL.json, unreadable
    LONGS_EQUAL((int)pp::Status::kBadValue, (int)o.status);
    STRCMP_CONTAINS("previous calibration", o.message.c_str());
  }
  {
    cal::Session session(sim.rig(), "PN-1", 7, false, Options("/proc/no-such/out"));
    LONGS_EQUAL((int)pp::Status::kIoError, (int)session.OpenOutput().status);
  }
  {
    cal::SessionOptions options = Options(dir);
    options.protocol.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
    options.protocol.compensator_operators = 32;  // more than the quick sweep tells apart
    cal::Session refused(sim.rig(), "PN-1", 7, false, options);
    LONGS_EQUAL((int)pp::Status::kInvalidArgument, (int)refused.CheckSweep().status);
    options.allow_fallback = true;
    cal::Session allowed(sim.rig(), "PN-1", 7, false, options);
    CHECK(allowed.CheckSweep().ok());
  }
}

TEST(CalibrationSession, AStoppedSessionKeepsItsJournalAndTheNextResumesIt) {
  const std::string dir = pt::MakeTempDir("palpa-session");
  {
    pt::SimRig sim({"thesis-5finger", 0, 0, 33});
    cal::Session session(sim.rig(), "PN-1", 7, false, Options(dir));
    CHECK(session.OpenOutput().ok());
    CHECK(session.LoadPrevious().ok());  // none yet
    const ph::Outcome o = session.Run([&](const cal::Progress& p) {
      if (p.done == 8) sim.force_lost = true;  // the force sensor drops out mid-sweep
    });
    LONGS_EQUAL((int)pp::Status::kUnavailable, (int)o.status);
    STRCMP_CONTAINS("force sensor lost", o.message.c_str());
  }
  CHECK(Exists(dir + "/PN-1.journal.json"));
  CHECK_FALSE(Exists(dir + "/PN-1.json"));  // nothing but the journal
  pt::SimRig sim({"thesis-5finger", 0, 0, 34});
  cal::SessionOptions options = Options(dir);
  options.resume = true;
  cal::Session session(sim.rig(), "PN-1", 7, false, options);
  const ph::Outcome o = session.Calibrate(nullptr);
  CHECK_TEXT(o.ok(), o.message.c_str());
  CHECK(Exists(dir + "/PN-1.json"));
  CHECK_FALSE(Exists(dir + "/PN-1.journal.json"));
  // That file now calibrates PN-1: another actuator's session refuses it as its previous one.
  options = Options(dir);
  options.previous = dir + "/PN-1.json";
  cal::Session other(sim.rig(), "PN-2", 7, false, options);
  const ph::Outcome refused = other.LoadPrevious();
  LONGS_EQUAL((int)pp::Status::kInvalidArgument, (int)refused.status);
  STRCMP_CONTAINS("calibrates PN-1, not PN-2", refused.message.c_str());
}

TEST(CalibrationSession, AForceLimitAndALostDeviceAreToldApartByTheirCode) {
  // The force limit below what touching the film takes: the run stops on it, out of range.
  pt::SimRig limited({"thesis-5finger", 0, 0, 35});
  cal::Rig rig = limited.rig();
  rig.limits.max_force_n = 0.01;
  cal::Session stopped(rig, "PN-1", 7, false, Options(pt::MakeTempDir("palpa-session")));
  CHECK(stopped.OpenOutput().ok());
  ph::Outcome o = stopped.Run(nullptr);
  CHECK(stopped.stopped());
  LONGS_EQUAL_TEXT((int)pp::Status::kOutOfRange, (int)o.status, o.message.c_str());
  STRCMP_CONTAINS("above the limit of 0.01 N", o.message.c_str());
  // The stage stops answering mid-run: unavailable, as a lost force sensor is.
  pt::SimRig lost({"thesis-5finger", 0, 0, 36});
  cal::Session session(lost.rig(), "PN-1", 7, false, Options(pt::MakeTempDir("palpa-session")));
  CHECK(session.OpenOutput().ok());
  o = session.Run([&](const cal::Progress& p) {
    if (p.done == 2) lost.stage_lost = true;
  });
  CHECK(session.stopped());
  LONGS_EQUAL_TEXT((int)pp::Status::kUnavailable, (int)o.status, o.message.c_str());
  STRCMP_CONTAINS("no answer from the stage", o.message.c_str());
}
