// Pen tablets: pressure levels to force (the thesis's exponential, fitted from presses), the pad
// mapped onto the tissue, and the libevdev adapter against recorded events replayed through a
// link-time fake of libevdev — reports, lost events (SYN_DROPPED), pads without pressure or
// resolution, devices that are not pads, and a device unplugged.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "fake_libevdev.h"
#include "palpa/host/scene_evdev.h"
#include "palpa/host/scene_tablet.h"

#include "CppUTest/TestHarness.h"
#include "text_checks.h"

namespace ph = palpa::host;
namespace pt = palpa::testing;

namespace {

std::string FitRefusal(const std::vector<ph::Press>& presses) {
  const auto fit = ph::FitPressureForce(presses);
  CHECK_TEXT(!fit.ok(), "fitted");
  return fit.message;
}

}  // namespace

TEST_GROUP(ScenePressure){};

TEST(ScenePressure, ThesisFormAtItsEnds) {
  const ph::PressureForce thesis;
  DOUBLES_EQUAL(0.0827, ph::ForceAtLevel(thesis, 0), 1e-12);
  DOUBLES_EQUAL(0.0827 * std::exp(0.0039 * 1023), ph::ForceAtLevel(thesis, 1023), 1e-12);
  DOUBLES_EQUAL(4.47, ph::ForceAtLevel(thesis, 1023), 0.01);
  CHECK(ph::CheckPressureForce(thesis).ok());
  CHECK_CONTAINS(ph::CheckPressureForce({0, 0.0039}).message, "a = 0 N");
  CHECK_CONTAINS(ph::CheckPressureForce({1, 0.01}).message, "at full pressure");
}

TEST(ScenePressure, FitRecoversTheFormFromPresses) {
  const ph::PressureForce truth{0.1, 0.003};
  std::vector<ph::Press> presses;
  for (double level : {50.0, 300.0, 600.0, 900.0})
    presses.push_back({level, ph::ForceAtLevel(truth, level)});
  const auto fit = ph::FitPressureForce(presses);
  CHECK_TEXT(fit.ok(), fit.message.c_str());
  DOUBLES_EQUAL(0.1, fit.value.model.a_n, 1e-9);
  DOUBLES_EQUAL(0.003, fit.value.model.b_per_level, 1e-12);
  DOUBLES_EQUAL(0, fit.value.rms_n, 1e-9);
  // A sensor's noise: ±2 % on each press moves the fit, not far.
  presses[0].force_n *= 1.02, presses[1].force_n *= 0.98, presses[2].force_n *= 1.02;
  const auto noisy = ph::FitPressureForce(presses);
  CHECK(noisy.ok());
  DOUBLES_EQUAL(0.003, noisy.value.model.b_per_level, 1e-4);
  CHECK(noisy.value.rms_n > 0 && noisy.value.max_error_n >= noisy.value.rms_n);
}

TEST(ScenePressure, FitRefusesWhatCannotBeFitted) {
  CHECK_CONTAINS(FitRefusal({}), "at least two at different levels");
  CHECK_CONTAINS(FitRefusal({{100, 1}, {100, 2}}), "at least two at different levels");
  CHECK_CONTAINS(FitRefusal({{100, 1}, {200, 0}}), "presses[1]: force 0 N");
  CHECK_CONTAINS(FitRefusal({{1100, 1}, {200, 1}}), "presses[0]: level 1100");
  CHECK_CONTAINS(FitRefusal({{0, 0.5}, {500, 90}}), "at full pressure");
}

TEST(ScenePressure, PressesReadLineByLine) {
  const auto ok = ph::ParsePresses("# five presses\nlevel, force_n\n100,0.12\n800,1.9\n", "p.csv");
  CHECK_TEXT(ok.ok(), ok.message.c_str());
  LONGS_EQUAL(2, ok.value.size());
  DOUBLES_EQUAL(1.9, ok.value[1].force_n, 0);
  CHECK_CONTAINS(ph::ParsePresses("level,force\n1,2\n", "p.csv").message,
                 "p.csv: line 1: expected the header level,force_n");
  CHECK_CONTAINS(ph::ParsePresses("level,force_n\n1\n", "p.csv").message, "p.csv: line 2");
  CHECK_CONTAINS(ph::ParsePresses("level,force_n\n1,x\n", "p.csv").message, "p.csv: line 2");
}

TEST_GROUP(ScenePad){};

TEST(ScenePad, AxesOntoTheTissueWithYUpwards) {
  ph::TabletMapping m;
  m.pad = {"pad", {0, 12500, 100}, {0, 8500, 100}, ph::PadAxis{0, 1023, 0}, true};
  m.extent_x_mm = 120, m.extent_y_mm = 30;
  CHECK(ph::CheckTabletMapping(m).ok());
  const ph::SceneInput corner = ph::MapPad(m, 1.5, 0, 0, 1023, true);
  DOUBLES_EQUAL(1.5, corner.time_s, 0);
  DOUBLES_EQUAL(0, corner.x_mm, 0);
  DOUBLES_EQUAL(30, corner.y_mm, 0);  // the pad's top edge is the tissue's far edge
  DOUBLES_EQUAL(ph::ForceAtLevel({}, 1023), corner.force_n, 1e-12);
  const ph::SceneInput mid = ph::MapPad(m, 0, 6250, 8500, 0, false);
  DOUBLES_EQUAL(60, mid.x_mm, 1e-12);
  DOUBLES_EQUAL(0, mid.y_mm, 1e-12);
  DOUBLES_EQUAL(0, mid.force_n, 0);  // lifted: no force, whatever the level
  // Past the axis's stated range (a pad's quirk): held at the tissue's edge.
  DOUBLES_EQUAL(120, ph::MapPad(m, 0, 13000, 0, 0, true).x_mm, 0);
  STRCMP_EQUAL("pad: 125 × 85 mm, 1024 pressure levels", ph::DescribePad(m.pad).c_str());
}

TEST(ScenePad, PressureRangeScaledToTheThesisLevels) {
  const ph::PadAxis p{0, 2047, 0};
  DOUBLES_EQUAL(1023, ph::PressureLevel(p, 2047), 1e-12);
  DOUBLES_EQUAL(1023.0 / 2, ph::PressureLevel(p, 1023.5), 1);
  const ph::PadAxis offset{100, 1123, 0};
  DOUBLES_EQUAL(0, ph::PressureLevel(offset, 50), 0);
}

TEST(ScenePad, NoPressureAxisPressesWithTheTouchForce) {
  ph::TabletMapping m;
  m.pad = {"touchpad", {0, 1000, 0}, {0, 500, 0}, std::nullopt, true};
  m.extent_x_mm = 10, m.extent_y_mm = 10, m.touch_force_n = 0.7;
  DOUBLES_EQUAL(0.7, ph::MapPad(m, 0, 5, 5, std::nullopt, true).force_n, 0);
  DOUBLES_EQUAL(0, ph::MapPad(m, 0, 5, 5, std::nullopt, false).force_n, 0);
  STRCMP_EQUAL("touchpad: size not stated, no pressure axis", ph::DescribePad(m.pad).c_str());
}

TEST(ScenePad, BadMappingsNamed) {
  ph::TabletMapping m;
  m.pad = {"flat", {5, 5, 0}, {0, 10, 0}, std::nullopt, false};
  m.extent_x_mm = 10, m.extent_y_mm = 10;
  CHECK_CONTAINS(ph::CheckTabletMapping(m).message,
                 "\"flat\": its absolute x axis (ABS_X) has no range");
  m.pad.x = {0, 10, 0};
  m.touch_force_n = -1;
  CHECK_CONTAINS(ph::CheckTabletMapping(m).message, "touch_force_n");
}

TEST_GROUP(SceneEvdev) {
  std::string dir, node;
  void setup() override {
    pt::ResetEvdev();
    char templ[] = "/tmp/palpa-evdev-XXXXXX";
    dir = mkdtemp(templ);
    // A FIFO stands for the event node: opened without blocking, never readable, so waiting for
    // events times out as on a quiet device.
    node = dir + "/event7";
    CHECK(mkfifo(node.c_str(), 0600) == 0);
  }
  void teardown() override {
    pt::ResetEvdev();  // what the test scripted, freed before the leak check
    unlink(node.c_str());
    rmdir(dir.c_str());
  }
  std::unique_ptr<ph::PenTablet> Open() {
    auto t = ph::PenTablet::Open(node, 120, 30, ph::PressureForce{}, 1.0);
    CHECK_TEXT(t.ok(), t.message.c_str());
    return std::move(t.value);
  }
  ph::SceneInput Next(ph::PenTablet & t) {
    const auto s = t.Next(5);
    CHECK_TEXT(s.ok(), s.message.c_str());
    CHECK_TEXT(s.value.has_value(), "no report");
    return *s.value;
  }
};

TEST(SceneEvdev, ReportsReplayedAsInputs) {
  pt::MakeTablet();
  pt::Report(10.000, 0, 9500, 0, false);
  pt::Report(10.010, 7600, 4750, 2047, true);
  pt::Report(10.020, 15200, 0, 1024, true);
  auto t = Open();
  LONGS_EQUAL(CLOCK_MONOTONIC, pt::Evdev().clock_id);
  STRCMP_EQUAL("Fake Pen Tablet: 152 × 95 mm, 2048 pressure levels",
               ph::DescribePad(t->mapping().pad).c_str());
  const ph::SceneInput lifted = Next(*t);
  DOUBLES_EQUAL(10.0, lifted.time_s, 1e-9);
  DOUBLES_EQUAL(0, lifted.x_mm, 1e-9);
  DOUBLES_EQUAL(0, lifted.y_mm, 1e-9);
  DOUBLES_EQUAL(0, lifted.force_n, 0);
  const ph::SceneInput middle = Next(*t);
  DOUBLES_EQUAL(10.01, middle.time_s, 1e-9);
  DOUBLES_EQUAL(60, middle.x_mm, 1e-9);
  DOUBLES_EQUAL(15, middle.y_mm, 1e-9);
  DOUBLES_EQUAL(ph::ForceAtLevel({}, 1023), middle.force_n, 1e-9);
  const ph::SceneInput far = Next(*t);
  DOUBLES_EQUAL(120, far.x_mm, 1e-9);
  DOUBLES_EQUAL(30, far.y_mm, 1e-9);
  DOUBLES_EQUAL(ph::ForceAtLevel({}, 1024.0 / 2047 * 1023), far.force_n, 1e-9);
  // Nothing more: the wait times out with nothing, not an error.
  const auto none = t->Next(5);
  CHECK(none.ok() && !none.value.has_value());
}

TEST(SceneEvdev, PartOfAReportIsNotAnInput) {
  pt::MakeTablet();
  pt::Report(1.0, 1000, 1000, 500, true);
  pt::Evdev().script.push_back({pt::EvdevStep::kEvent, pt::Ev(1.01, EV_ABS, ABS_X, 2000), {}});
  auto t = Open();
  Next(*t);
  const auto half = t->Next(5);
  CHECK(half.ok() && !half.value.has_value());
}

TEST(SceneEvdev, DroppedEventsResyncedFromTheDevicesState) {
  pt::MakeTablet();
  pt::Report(1.00, 1000, 9500, 500, true);
  // The first half of a report arrives, then the kernel's buffer overflows: the rest of that
  // report and two more are lost. The reader must not report the half (x moved, y not), nor
  // the lost positions, but where the pen is after the loss.
  pt::Evdev().script.push_back({pt::EvdevStep::kEvent, pt::Ev(1.01, EV_ABS, ABS_X, 1100), {}});
  pt::EvdevStep drop{pt::EvdevStep::kDropped, pt::Ev(1.01, EV_SYN, SYN_DROPPED, 0), {}};
  for (const input_event& e :
       {pt::Ev(1.01, EV_ABS, ABS_Y, 9400), pt::Ev(1.01, EV_SYN, SYN_REPORT, 0),
        pt::Ev(1.02, EV_ABS, ABS_X, 1200), pt::Ev(1.02, EV_SYN, SYN_REPORT, 0),
        pt::Ev(1.03, EV_ABS, ABS_X, 1300), pt::Ev(1.03, EV_ABS, ABS_Y, 9300),
        pt::Ev(1.03, EV_ABS, ABS_PRESSURE, 1500), pt::Ev(1.03, EV_SYN, SYN_REPORT, 0)}) {
    drop.lost.push_back(e);
  }
  pt::Evdev().script.push_back(drop);
  pt::Report(1.04, 1400, 9200, 1500, true);
  auto t = Open();
  Next(*t);
  const ph::SceneInput resynced = Next(*t);
  LONGS_EQUAL(1, t->resyncs());
  DOUBLES_EQUAL(1.03, resynced.time_s, 1e-9);
  DOUBLES_EQUAL(1300.0 / 15200 * 120, resynced.x_mm, 1e-9);
  DOUBLES_EQUAL((1 - 9300.0 / 9500) * 30, resynced.y_mm, 1e-9);
  DOUBLES_EQUAL(ph::ForceAtLevel({}, 1500.0 / 2047 * 1023), resynced.force_n, 1e-9);
  const ph::SceneInput after = Next(*t);
  DOUBLES_EQUAL(1.04, after.time_s, 1e-9);
  DOUBLES_EQUAL(1400.0 / 15200 * 120, after.x_mm, 1e-9);
}

TEST(SceneEvdev, TouchpadWithoutPressureOrResolution) {
  auto& f = pt::Evdev();
  f.name = "Fake Touchpad";
  f.abs[{EV_ABS, ABS_X}] = input_absinfo{0, 1200, 5600, 0, 0, 0};
  f.abs[{EV_ABS, ABS_Y}] = input_absinfo{0, 1000, 4800, 0, 0, 0};
  f.codes.push_back({EV_KEY, BTN_TOUCH});
  for (const input_event& e : {pt::Ev(2, EV_ABS, ABS_X, 3400), pt::Ev(2, EV_ABS, ABS_Y, 2900),
                               pt::Ev(2, EV_KEY, BTN_TOUCH, 1), pt::Ev(2, EV_SYN, SYN_REPORT, 0)})
    f.script.push_back({pt::EvdevStep::kEvent, e, {}});
  auto t = Open();
  STRCMP_EQUAL("Fake Touchpad: size not stated, no pressure axis",
               ph::DescribePad(t->mapping().pad).c_str());
  const ph::SceneInput s = Next(*t);
  DOUBLES_EQUAL(60, s.x_mm, 1e-9);
  DOUBLES_EQUAL(15, s.y_mm, 1e-9);
  DOUBLES_EQUAL(1.0, s.force_n, 0);  // the touch force: the pad cannot say how hard
}

TEST(SceneEvdev, PressureWithoutTouchButtonTouchesAbovePressureMinimum) {
  auto& f = pt::Evdev();
  f.abs[{EV_ABS, ABS_X}] = input_absinfo{0, 0, 100, 0, 0, 0};
  f.abs[{EV_ABS, ABS_Y}] = input_absinfo{0, 0, 100, 0, 0, 0};
  f.abs[{EV_ABS, ABS_PRESSURE}] = input_absinfo{0, 0, 1023, 0, 0, 0};
  for (int p : {0, 1}) {
    f.script.push_back({pt::EvdevStep::kEvent, pt::Ev(3 + p, EV_ABS, ABS_PRESSURE, p), {}});
    f.script.push_back({pt::EvdevStep::kEvent, pt::Ev(3 + p, EV_SYN, SYN_REPORT, 0), {}});
  }
  auto t = Open();
  DOUBLES_EQUAL(0, Next(*t).force_n, 0);
  DOUBLES_EQUAL(ph::ForceAtLevel({}, 1), Next(*t).force_n, 1e-12);
}

TEST(SceneEvdev, DevicesThatAreNotPadsNamedWithWhatTheyLack) {
  auto& f = pt::Evdev();
  f.name = "Logitech USB Optical Mouse";
  f.codes.push_back({EV_REL, REL_X});
  const auto mouse = ph::PenTablet::Open(node, 120, 30, {}, 1.0);
  CHECK(!mouse.ok());
  CHECK_CONTAINS(mouse.message,
                 node + " (\"Logitech USB Optical Mouse\") is not a pen tablet or touchpad");
  CHECK_CONTAINS(mouse.message, "it has no absolute x axis (ABS_X) and no absolute y axis (ABS_Y)");
  CHECK(f.freed);
  f.abs[{EV_ABS, ABS_X}] = input_absinfo{0, 0, 100, 0, 0, 0};
  const auto no_y = ph::PenTablet::Open(node, 120, 30, {}, 1.0);
  CHECK_CONTAINS(no_y.message, "it has no absolute y axis (ABS_Y)");
  f.abs[{EV_ABS, ABS_Y}] = input_absinfo{0, 0, 0, 0, 0, 0};
  CHECK_CONTAINS(ph::PenTablet::Open(node, 120, 30, {}, 1.0).message,
                 "absolute y axis (ABS_Y) has no range (0 … 0)");
  f.evdev = false;
  CHECK_CONTAINS(ph::PenTablet::Open(node, 120, 30, {}, 1.0).message,
                 node + ": not an input event device");
  CHECK_CONTAINS(ph::PenTablet::Open(dir + "/event99", 120, 30, {}, 1.0).message,
                 dir + "/event99: No such file or directory");
}

TEST(SceneEvdev, UnpluggedDeviceIsAnErrorNamingIt) {
  pt::MakeTablet();
  pt::Report(1, 10, 10, 10, true);
  pt::Evdev().script.push_back({pt::EvdevStep::kGone, {}, {}});
  auto t = Open();
  Next(*t);
  const auto gone = t->Next(5);
  CHECK(!gone.ok());
  CHECK_CONTAINS(gone.message, node + " (\"Fake Pen Tablet\"): reading failed, the device is gone");
}
