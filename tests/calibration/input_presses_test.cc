// Pen pressure calibration on virtual time: a hand presses a pen on a force sensor of the
// rig's class (Nano17 noise, an offset the tare removes), each press ramped, held with a tremor
// and released; the presses collected fit the pen's true exponential. A press at a level already
// taken is asked again, a hand that never presses runs out of time, a pen that goes away stops
// the run.
#include <cmath>
#include <random>
#include <vector>

#include "palpa/calibration/input_presses.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace ph = palpa::host;

namespace {

const ph::PressureForce kTruth{0.09, 0.0036};

struct VirtualTime : cal::RigTime {
  double now = 0;
  double Now() override { return now; }
  void Wait(double s) override { now += s; }
};

/// A hand: each press ramps to its level in 0.3 s, holds 1 s with a ±2-level tremor, releases in
/// 0.2 s, then rests lifted 0.5 s. Before the first, 0.5 s lifted.
struct Hand {
  std::vector<double> levels;
  double Level(double t, bool* touching) const {
    double at = 0.5;
    *touching = false;
    for (double level : levels) {
      const double u = t - at;
      if (u < 0) return 0;
      if (u < 2.0) {
        *touching = u < 1.5;
        if (u < 0.3) return level * u / 0.3;
        if (u < 1.3) return level + 2 * std::sin(2 * M_PI * 7 * u);
        return std::max(0.0, level * (1.5 - u) / 0.2);
      }
      at += 2.0;
    }
    return 0;
  }
};

struct Pen : cal::PenLevels {
  VirtualTime& time;
  const Hand& hand;
  bool gone = false;
  Pen(VirtualTime& t, const Hand& h) : time(t), hand(h) {}
  ph::Result<std::optional<cal::PenState>> Next(int) override {
    time.Wait(0.01);  // a report every 10 ms
    if (gone) return {ph::Status::kIoError, "pen: the device is gone"};
    cal::PenState s;
    s.level = std::round(hand.Level(time.now, &s.touching));
    return std::optional<cal::PenState>(s);
  }
};

struct Sensor : cal::ForceSensor {
  VirtualTime& time;
  const Hand& hand;
  std::mt19937 rng{11};
  std::normal_distribution<double> noise{0, cal::kNano17NoiseN};
  double offset = 0.05, tare = 0;
  Sensor(VirtualTime& t, const Hand& h) : time(t), hand(h) {}
  double Raw() {
    bool touching = false;
    const double level = hand.Level(time.now, &touching);
    return offset + (touching ? ph::ForceAtLevel(kTruth, level) : 0.0) + noise(rng);
  }
  cal::RigStatus Read(double* n) override {
    *n = Raw() - tare;
    return {};
  }
  cal::RigStatus Tare() override {
    tare = Raw();
    return {};
  }
};

}  // namespace

TEST_GROUP(InputPresses){};

TEST(InputPresses, PressesFitThePensOwnExponential) {
  VirtualTime time;
  Hand hand{{150, 400, 420, 650, 850, 1000}};  // the third too close to the second
  Pen pen(time, hand);
  Sensor sensor(time, hand);
  std::vector<std::string> said;
  const auto presses =
      cal::CollectPresses(pen, sensor, time, {}, [&](const std::string& s) { said.push_back(s); });
  CHECK_TEXT(presses.ok(), presses.message.c_str());
  LONGS_EQUAL(5, presses.value.size());
  DOUBLES_EQUAL(150, presses.value[0].level, 3);
  DOUBLES_EQUAL(650, presses.value[2].level, 3);
  bool asked_again = false;
  for (const auto& s : said) asked_again |= s.find("within 60 of press 2") != std::string::npos;
  CHECK(asked_again);
  const auto fit = ph::FitPressureForce(presses.value);
  CHECK_TEXT(fit.ok(), fit.message.c_str());
  DOUBLES_EQUAL(kTruth.b_per_level, fit.value.model.b_per_level, 0.02 * kTruth.b_per_level);
  DOUBLES_EQUAL(kTruth.a_n, fit.value.model.a_n, 0.05 * kTruth.a_n);
  CHECK(fit.value.rms_n < 0.02);
}

TEST(InputPresses, AHandThatNeverPressesRunsOutOfTime) {
  VirtualTime time;
  Hand hand{};
  Pen pen(time, hand);
  Sensor sensor(time, hand);
  cal::PressOptions o;
  o.timeout_s = 3;
  const auto presses = cal::CollectPresses(pen, sensor, time, o, [](const std::string&) {});
  CHECK(!presses.ok());
  STRCMP_CONTAINS("time ran out after 0 of 5 presses", presses.message.c_str());
}

TEST(InputPresses, APenThatGoesAwayStopsTheRun) {
  VirtualTime time;
  Hand hand{{300}};
  Pen pen(time, hand);
  Sensor sensor(time, hand);
  pen.gone = true;
  const auto presses = cal::CollectPresses(pen, sensor, time, {}, [](const std::string&) {});
  CHECK(!presses.ok());
  STRCMP_CONTAINS("the device is gone", presses.message.c_str());
}
