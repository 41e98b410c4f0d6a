// Calibration procedures on the in-process simulated rig (virtual time): contact detection and
// zeroing, the regulator's static correction, a deformation sweep against Table 5-4, a press
// against the truth, and every safety stop leaving the rig retracted and the board vented.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "palpa/calibration/procedures.h"
#include "sim_rig.h"

#include "palpa/hal/sim/plant_params.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace pt = palpa::testing;
namespace pp = palpa::protocol;

TEST_GROUP(Procedures){};

TEST(Procedures, ZeroAndSurfaceHeightsFollowTheFilm) {
  pt::SimRig sim({"thesis-5finger", 0, 1, 3});
  cal::Rig rig = sim.rig();
  cal::ContactOptions o;
  double zero = 0;
  const cal::RigStatus s = cal::ZeroOnVentedSurface(rig, 0, o, &zero);
  CHECK_TEXT(s.ok(), s.message.c_str());
  DOUBLES_EQUAL(0, zero, 0.06);  // the detection lag: threshold / contact stiffness
  CHECK(sim.SetDrive(0, 40, 0).ok());
  sim.Wait(3);
  // Each touch reads the film within the rig's repeatability (2.82 % per reading, thesis): eight
  // touches average within 10 µm and three standard errors of the truth, and scatter about that.
  const double truth = sim.board().sim().plant().Truth().fingers[0].deformation_mm;
  CHECK(truth > 1.0);
  constexpr int kTouches = 8;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < kTouches; ++k) {
    double surface = 0;
    CHECK(cal::FindSurface(rig, zero, o, &surface).ok());
    const double e = (surface - zero - truth) / truth;
    sum += e;
    sum2 += e * e;
  }
  const double r = palpa::sim::params::kRigRepeatability;
  const double mean = sum / kTouches, sd = std::sqrt(sum2 / kTouches - mean * mean);
  CHECK_TEXT(std::fabs(mean) * truth < 0.01 + 3 * r * truth / std::sqrt(kTouches),
             std::to_string(mean).c_str());
  CHECK_TEXT(sd > 0.3 * r && sd < 2.5 * r, std::to_string(sd).c_str());
}

TEST(Procedures, AnIndenterLiftedClearOfTheFilmDoesNotTouchItAgain) {
  // Each touch reads the film off by the rig's repeatability, drawn anew once the indenter has
  // gone 0.1 mm clear. Were the new error in force at once, the surface (3.4 mm up, each draw
  // moving it by 0.1 mm) could jump onto the indenter still rising: a touch no motion made, one
  // draw more, and whether it came would turn on a fraction of a micrometre of travel (two hosts
  // reading late and on time then calibrated with different draws from there on).
  pt::SimRig sim({"thesis-5finger", 0, 1, 3});
  CHECK(sim.SetDrive(0, 80, 0).ok());
  sim.Wait(3);
  const palpa::sim::Plant& plant = sim.board().sim().plant();
  auto travel = [&](double mm, const std::function<void(float)>& each) {
    CHECK(sim.MoveTo(mm, 2.0).ok());
    for (bool moving = true; moving;) {
      sim.Wait(0.001);
      each(sim.model().true_force_n());
      CHECK(sim.Moving(&moving).ok());
    }
  };
  int touches = 0, untouched = 0;
  for (int k = 0; k < 20; ++k) {
    const double surface = plant.Truth().fingers[0].deformation_mm;
    travel(surface - 0.4, [&](float) {});
    touches += sim.model().true_force_n() > 0;
    bool clear = false;
    travel(surface + 0.5, [&](float force) {
      untouched += clear && force > 0;
      clear = clear || force <= 0;
    });
  }
  LONGS_EQUAL(20, touches);
  LONGS_EQUAL(0, untouched);
}

TEST(Procedures, AFastApproachFindsTheSurfaceAsASlowOneDoesWhenReadingsArriveLate) {
  // The quick protocol's 1 mm/s approach, with each force reading arriving 30 ms late (a busy
  // host): the stage is 30 µm deeper by the time the host sees contact, and with the position read
  // after it, 30–60 µm. The last stretch is crept at 0.1 mm/s, where the same lateness costs a
  // tenth: the surface stays within the sensor's noise and 6 µm of lateness of the prompt one.
  cal::ContactOptions o;
  o.speed_mm_s = 1.0;
  auto surface = [&o](double latency_s, double kpa) {
    pt::SimRig sim({"thesis-5finger", 0, 1, 3});
    cal::Rig rig = sim.rig();
    double zero = 0, found = 0;
    CHECK(cal::ZeroOnVentedSurface(rig, 0, o, &zero).ok());
    CHECK(sim.SetDrive(0, kpa, 0).ok());
    sim.Wait(3);
    sim.force_latency_s = latency_s;
    const cal::RigStatus s = cal::FindSurface(rig, zero, o, &found);
    CHECK_TEXT(s.ok(), s.message.c_str());
    return found;
  };
  for (double kpa : {0.0, 40.0}) DOUBLES_EQUAL(surface(0, kpa), surface(0.03, kpa), 0.02);
}

TEST(Procedures, ASearchClimbingToTheUpperLimitSaysTheZeroMayHaveWalked) {
  // A zero walking 20 mN a second from its tare reads as contact at every height: the search
  // backs off to the stage's upper limit and says what the sensor reads there, far above the film.
  pt::SimRig sim({"thesis-5finger", 0, 1, 3});
  cal::Rig rig = sim.rig();
  const cal::ContactOptions o;
  double zero = 0, found = 0;
  CHECK(cal::ZeroOnVentedSurface(rig, 0, o, &zero).ok());
  sim.force_drift_n_per_s = 0.02;
  const cal::RigStatus s = cal::FindSurface(rig, zero, o, &found);
  CHECK_FALSE(s.ok());
  STRCMP_CONTAINS("still in contact at the stage's upper limit: the force sensor reads",
                  s.message.c_str());
  STRCMP_CONTAINS("if nothing touches the indenter there, the sensor's zero has walked",
                  s.message.c_str());
}

TEST(Procedures, AStageThatStopsOnForceFindsTheSameSurfaceHoweverLateTheHostReads) {
  // A loaded machine: each force reading reaches the host 0.1 or 0.3 s of board time late (25 or
  // 75 ms at the demo's 4x). Polled, the stage is then deeper when the host sees contact — tens
  // of µm even on the last stretch at 0.1 mm/s. A stage that stops itself on its load cell
  // stops where the force reached the threshold, on the rig's clock: the zero and the surface
  // over the film at 40 kPa are where they are with prompt readings, to a µm.
  cal::ContactOptions o;
  o.speed_mm_s = 1.0;  // the quick protocol's approach
  struct Found {
    double zero, surface;
  };
  auto find = [&o](bool force_stop, double latency_s) {
    pt::SimRig sim({"thesis-5finger", 0, 1, 3});
    sim.force_stop = force_stop;
    sim.force_latency_s = latency_s;
    cal::Rig rig = sim.rig();
    Found f{};
    CHECK(cal::ZeroOnVentedSurface(rig, 0, o, &f.zero).ok());
    CHECK(sim.SetDrive(0, 40, 0).ok());
    sim.Wait(3);
    const cal::RigStatus s = cal::FindSurface(rig, f.zero, o, &f.surface);
    CHECK_TEXT(s.ok(), s.message.c_str());
    return f;
  };
  const Found prompt = find(true, 0), polled_prompt = find(false, 0);
  for (double latency : {0.03, 0.1, 0.2, 0.3}) {
    const Found late = find(true, latency);
    DOUBLES_EQUAL(prompt.zero, late.zero, 0.002);  // two encoder counts
    // The film itself moves by a few µm with the line's pressure noise between the two runs.
    DOUBLES_EQUAL(prompt.surface, late.surface, 0.01);
    // Polled, the zero alone moves 13 to 54 µm: what a loaded machine did to the demo.
    CHECK(std::fabs(find(false, latency).zero - polled_prompt.zero) > 0.01);
  }
}

TEST(Procedures, RegulatorCorrectionShowsTheStaticErrorAndTheBoardTakesIt) {
  pt::SimRig sim({"thesis-5finger", 0, 1, 4});
  cal::Rig rig = sim.rig();
  std::vector<pp::CorrectionPoint> points;
  const cal::RigStatus s = cal::RegulatorCorrection(rig, 0, 0, 6, 1.5, &points);
  CHECK_TEXT(s.ok(), s.message.c_str());
  LONGS_EQUAL(6, points.size());
  double largest = 0;
  for (const auto& p : points) {
    CHECK(std::abs(p.rising_pa - p.command_pa) < 3000);  // within the regulator's class
    largest = std::max<double>(largest, std::abs(p.rising_pa - p.command_pa));
  }
  CHECK(largest > 100);  // feed-forward alone shows the regulator's own error
  // The falling branch is measured coming down from above the top point, so the top's falling
  // reading is a falling one (the regulator's hysteresis above the rising one), as at the points
  // below it; straight after the rising sweep it would be the rising reading again.
  const auto gap = [](const pp::CorrectionPoint& p) { return p.falling_pa - p.rising_pa; };
  const double middle = gap(points[points.size() / 2]);
  CHECK_TEXT(middle > 100, std::to_string(middle).c_str());
  CHECK_TEXT(gap(points.back()) > 0.5 * middle, std::to_string(gap(points.back())).c_str());
  pp::ConfigureLine line = sim.board().config().lines[0];
  line.correction_count = static_cast<uint8_t>(points.size());
  std::copy(points.begin(), points.end(), line.correction.begin());
  CHECK(palpa::core::ValidateLine(line, nullptr) == pp::Status::kOk);
  DOUBLES_EQUAL(0.1, sim.board().config().lines[0].trim_kp, 1e-6);  // the trim is back
}

TEST(Procedures, DeformationSweepMatchesTable54) {
  pt::SimRig sim({"thesis-5finger", 0, 0, 5});
  cal::Rig rig = sim.rig();
  cal::ContactOptions o;
  o.speed_mm_s = 0.2;
  double zero = 0;
  CHECK(cal::ZeroOnVentedSurface(rig, 0, o, &zero).ok());
  std::vector<double> up, down;
  for (int k = 10; k <= 90; k += 20) up.push_back(k);
  for (int k = 90; k >= 10; k -= 20) down.push_back(k);
  std::vector<cal::SweepSample> rising, falling;
  CHECK(cal::DeformationSweep(rig, 0, up, 2, zero, o, &rising).ok());
  CHECK(sim.SetDrive(0, 100, 0).ok());  // the top of the major loop
  sim.Wait(2);
  CHECK(cal::DeformationSweep(rig, 0, down, 2, zero, o, &falling).ok());
  auto fit = [](const std::vector<cal::SweepSample>& s) {
    std::vector<std::pair<double, double>> xy;
    for (const auto& p : s) xy.push_back({p.drive_pa / 1000, p.output / 1000});
    return cal::FitLine(xy);
  };
  const cal::Line r = fit(rising), f = fit(falling);
  DOUBLES_EQUAL(0.0428, r.slope, 0.1 * 0.0428);  // Table 5-4's inflation fit, mm/kPa
  DOUBLES_EQUAL(0.0475, f.slope, 0.1 * 0.0475);  // and deflation
  CHECK(r.r2 > 0.95 && f.r2 > 0.95);
  CHECK(falling[2].output > rising[2].output + 200);  // at 50 kPa the branches are ≈ 0.4 mm apart
}

TEST(Procedures, APressGivesTheStiffnessAndALoopSmallerThanItsWork) {
  pt::SimRig sim({"thesis-5finger", 3, 0, 6});
  cal::Rig rig = sim.rig();
  cal::ContactOptions o;
  double zero = 0;
  CHECK(cal::ZeroOnVentedSurface(rig, 3, o, &zero).ok());
  CHECK(sim.SetDrive(3, 20, -60).ok());
  sim.Wait(4);
  cal::PressCycle cycle;
  const cal::RigStatus s = cal::Press(rig, zero, 3.0, 0.5, &cycle);
  CHECK_TEXT(s.ok(), s.message.c_str());
  const double truth = sim.board().sim().plant().Truth().fingers[3].stiffness_n_per_mm;
  DOUBLES_EQUAL(truth, cycle.stiffness_n_per_mm, 0.05 * truth);
  CHECK(cycle.r2 > 0.99);
  CHECK(cycle.loop_area_mj > 0);
  CHECK(cycle.loop_area_mj < 0.5 * cycle.peak_force_n * 3.0);  // below the press's loading work
}

TEST(Procedures, EverySafetyStopRetractsAndVents) {
  struct Case {
    const char* name;
    std::function<void(pt::SimRig&, cal::Rig&)> arm;
    const char* reason;
  };
  const Case cases[] = {
      {"force limit", [](pt::SimRig&, cal::Rig& rig) { rig.limits.max_force_n = 0.5; },
       "above the limit"},
      {"depth limit", [](pt::SimRig&, cal::Rig& rig) { rig.limits.min_position_mm = -1.0; },
       "outside the stage's limits"},
      {"force sensor lost", [](pt::SimRig& sim, cal::Rig&) { sim.force_lost = true; },
       "force sensor lost"},
      {"board fault", [](pt::SimRig& sim, cal::Rig&) { sim.board().Send(pp::EStop{}); },
       "board fault: estop_command"},
  };
  for (const Case& c : cases) {
    pt::SimRig sim({"thesis-5finger", 3, 0, 7});
    cal::Rig rig = sim.rig();
    double zero = 0;
    CHECK(cal::ZeroOnVentedSurface(rig, 3, cal::ContactOptions{}, &zero).ok());
    CHECK(sim.SetDrive(3, 20, -80).ok());
    sim.Wait(3);
    c.arm(sim, rig);
    cal::PressCycle cycle;
    const cal::RigStatus s = cal::Press(rig, zero, 3.0, 0.5, &cycle);
    CHECK_FALSE_TEXT(s.ok(), c.name);
    CHECK_TEXT(s.message.find(c.reason) != std::string::npos,
               (std::string(c.name) + ": " + s.message).c_str());
    sim.force_lost = false;
    sim.Wait(3);
    DOUBLES_EQUAL_TEXT(rig.limits.retract_mm, sim.model().PositionMm(), 0.01, c.name);  // retracted
    const double vacuum = sim.board().sim().plant().Truth().lines[5].chamber_pa;
    CHECK_TEXT(vacuum > -5000, c.name);  // vented (or safe): the vacuum released
    CHECK_TEXT(sim.model().true_force_n() == 0, c.name);
  }
}
