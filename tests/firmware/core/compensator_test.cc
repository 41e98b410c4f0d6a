// Compensators: the analytic PI inverse against its own forward model, memory from the applied
// drive, homing, the branch reversal rule, saturation, and every way parameters are refused.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "palpa/core/compensator.h"
#include "palpa/core/internal/compensator_tables.h"

#include "CppUTest/TestHarness.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

namespace {

pp::ConfigureFinger With(pp::CompensatorKind kind, const std::vector<float>& params) {
  pp::ConfigureFinger f{};
  f.compensator = kind;
  f.param_count = static_cast<uint8_t>(params.size());
  for (size_t i = 0; i < params.size(); ++i) f.params[i] = params[i];
  return f;
}

/// pi parameters with n operators over 0..50 kPa; some weights negative, all cumulative > 0.
std::vector<float> PiParams(int n, std::mt19937& rng, float offset = 0) {
  std::uniform_real_distribution<float> weight(-0.002f, 0.01f);
  std::vector<float> p{offset, 0.01f};
  for (int i = 0; i < n; ++i) p.push_back(50000.0f * static_cast<float>(i) / static_cast<float>(n));
  for (int i = 0; i < n; ++i) p.push_back(weight(rng));
  return p;
}

/// How close the inverse must land: 0.1 % of the target, or what four of the memory's drive steps
/// make at the model's steepest slope (the largest W_i of the pi parameters `p` from index
/// `w0_at`; the integer tables resolve the drive to ≈ 3 Pa here).
float Resolution(const pc::Compensator& c, const std::vector<float>& p, size_t w0_at, int n,
                 float y) {
  float cumulative = p[w0_at];
  float steepest = cumulative;
  for (int i = 0; i < n; ++i) steepest = std::max(steepest, cumulative += p[w0_at + 1 + n + i]);
  return std::max(1e-3f * y, 4 * c.play.drive_step * steepest);
}

float Play(float z, float u, float r) { return std::max(u - r, std::min(u + r, z)); }

/// The analytic PI inverse in double straight from the parameters (no integer tables): memory z
/// (Pa) follows the applied drive, then the inverse states follow v; returns the drive.
double ReferenceDrive(const std::vector<float>& p, int n, std::vector<double>& z, double applied,
                      double v) {
  const double w0 = p[1];
  double drive = v / w0;
  for (int i = 0; i < n; ++i) {
    const double r = p[2 + i];
    z[i] = std::max(applied - r, std::min(applied + r, z[i]));
  }
  double before = w0;
  double weighted_thresholds = 0;
  for (int i = 0; i < n; ++i) {
    const double r = p[2 + i];
    const double w = p[2 + n + i];
    const double cumulative = before + w;
    weighted_thresholds += w * r;
    const double inverse_threshold = cumulative * r - weighted_thresholds;
    double state = cumulative * z[i];
    for (int j = i + 1; j < n; ++j) state += p[2 + n + j] * z[j];
    state = std::max(v - inverse_threshold, std::min(v + inverse_threshold, state));
    drive += -w / (cumulative * before) * state;
    before = cumulative;
  }
  return drive;
}

double Uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

}  // namespace

TEST_GROUP(Compensator) { std::mt19937 rng{7}; };

TEST(Compensator, PiInverseReachesTheTargetOfItsForwardModelFromAnyMemory) {
  for (int n : {1, 4, 16, 32}) {
    const auto params = PiParams(n, rng, 5);
    const auto f = With(pp::CompensatorKind::kPrandtlIshlinskii, params);
    CHECK(pc::CompensatorParamsError(f) == nullptr);
    const pc::Compensator c = pc::MakeCompensator(f, 100000);
    pc::CompensatorState s;
    pc::HomeCompensator(c, s);
    std::uniform_real_distribution<float> target(10, 900);
    float applied = 0;
    for (int k = 0; k < 2000; ++k) {
      const float y = target(rng);
      const pc::CompensatorOutput out = pc::StepCompensator(c, s, y, applied);
      if (out.saturated) continue;
      // From the memory the step left, the forward model at the drive gives the target back.
      DOUBLES_EQUAL(y, pc::PlayForward(c, s, out.drive), Resolution(c, params, 1, n, y));
      applied = out.drive;
    }
  }
}

// The integer tables choose their scales per parameter set; at every scale a valid set can
// take they must give the float model's drive to within their resolution: a wrapped sum or an
// overflowed lane would be off by the whole range.
TEST(Compensator, PiIntegerTablesGiveTheFloatModelsDriveAtEveryScale) {
  int compared = 0;
  for (int set = 0; set < 300; ++set) {
    const int n = 1 + static_cast<int>(rng() % 32);
    const double w0 = std::pow(10.0, Uniform(rng, -6, 2));
    const double top = std::pow(10.0, Uniform(rng, 1, 5)) * 0.99;
    std::vector<float> p{static_cast<float>(Uniform(rng, -100, 100)), static_cast<float>(w0)};
    double r = Uniform(rng, 0, top / n);
    for (int i = 0; i < n; ++i, r += Uniform(rng, 0.2, 1.8) * top / n)
      p.push_back(static_cast<float>(std::min(r, 99999.0)));
    for (int i = 1; i < n; ++i) p[2 + i] = std::max(p[2 + i], std::nextafter(p[1 + i], 1e9f));
    double cumulative = w0;
    for (int i = 0; i < n; ++i) {
      double w = Uniform(rng, -0.6, 3.0) * w0;
      if (cumulative + w < 0.05 * w0) w = w0;
      cumulative += w;
      p.push_back(static_cast<float>(w));
    }
    const auto f = With(pp::CompensatorKind::kPrandtlIshlinskii, p);
    if (pc::CompensatorParamsError(f) != nullptr) continue;  // thresholds bunched at the top
    const pc::Compensator c = pc::MakeCompensator(f, 100000);
    double inverse_weights = 1 / w0;  // Σ |w'_i| with 1/w0: how state errors reach the drive
    double before = w0;
    for (int i = 0; i < n; ++i) {
      inverse_weights += std::abs(p[2 + n + i] / ((before + p[2 + n + i]) * before));
      before += p[2 + n + i];
    }
    const double state_step = 65536.0 * c.play.sum_step;
    pc::CompensatorState s;
    pc::HomeCompensator(c, s);
    double applied = 0;
    for (int k = 0; k < 60; ++k) {
      std::vector<double> z(n);
      for (int i = 0; i < n; ++i) z[i] = pc::PlayState(c, s, static_cast<uint8_t>(i));
      const double v = Uniform(rng, 0, cumulative * 100000);
      const auto out =
          pc::StepCompensator(c, s, static_cast<float>(v + p[0]), static_cast<float>(applied));
      // The reference sees the applied drive as the memory holds it: in whole drive steps.
      const double held = std::round(applied / c.play.drive_step) * c.play.drive_step;
      const double expected = ReferenceDrive(p, n, z, held, v);
      if (expected < 0 || expected > 100000) continue;  // clamped and flagged (tested below)
      const double tolerance =
          inverse_weights * state_step * (1 + n / 4.0) + 1e-4 * expected + 1e-3;
      if (std::abs(out.drive - expected) > tolerance) {
        FAIL(("set " + std::to_string(set) + " n " + std::to_string(n) + " step " +
              std::to_string(k) + ": drive " + std::to_string(out.drive) + " expected " +
              std::to_string(expected) + " within " + std::to_string(tolerance))
                 .c_str());
      }
      ++compared;
      applied = out.drive;
    }
  }
  CHECK(compared > 5000);  // most sets valid, most targets reachable
}

// What the integer tables cost in accuracy on a finger like the thesis's (16 operators over
// 50 kPa, ≈ 2 mm over 100 kPa): against the exact inverse in double with the exact applied drive,
// a few pascal — far inside the regulator's 0.2 % F.S. (200 Pa) sensitivity.
TEST(Compensator, PiDriveIsWithinAFewPascalOfTheExactInverseOnAThesisLikeFinger) {
  const int n = 16;
  std::vector<float> p{0, 0.008f};
  for (int i = 0; i < n; ++i) p.push_back(50000.0f * static_cast<float>(i) / n);
  for (int i = 0; i < n; ++i)
    p.push_back(0.012f / n * (1 + 0.5f * std::sin(static_cast<float>(i))));
  const pc::Compensator c =
      pc::MakeCompensator(With(pp::CompensatorKind::kPrandtlIshlinskii, p), 100000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  std::vector<double> z(p.begin() + 2, p.begin() + 2 + n);  // homed: on the upper clamps
  std::normal_distribution<double> lag(0, 300);             // the chamber never quite arrives
  double applied = 0;
  double worst = 0;
  for (int k = 0; k < 5000; ++k) {
    const double v = Uniform(rng, 50, 1800);
    const auto out = pc::StepCompensator(c, s, static_cast<float>(v), static_cast<float>(applied));
    const double expected = ReferenceDrive(p, n, z, applied, v);
    if (!out.saturated) worst = std::max(worst, std::abs(out.drive - expected));
    applied = std::max(0.0, out.drive + lag(rng));
  }
  CHECK(worst > 0);   // integer arithmetic, so not exact ...
  CHECK(worst < 10);  // ... but within 10 Pa
}

TEST(Compensator, AsymmetricPiInvertsThroughItsDeadZones) {
  std::vector<float> p{8, 0};
  const auto pi = PiParams(8, rng, 3);
  p.insert(p.end(), pi.begin() + 1, pi.end());  // w0, r, w (offset set above)
  p[1] = 3;
  for (float v : {100.0f, 300.0f, 600.0f}) p.push_back(v);  // dead-zone thresholds
  for (float g : {0.5f, -0.8f, 1.0f}) p.push_back(g);       // slopes 1.5, 0.7, 1.7
  const auto f = With(pp::CompensatorKind::kAsymmetricPi, p);
  CHECK(pc::CompensatorParamsError(f) == nullptr);
  const pc::Compensator c = pc::MakeCompensator(f, 100000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  float applied = 0;
  std::uniform_real_distribution<float> target(5, 1200);
  for (int k = 0; k < 2000; ++k) {
    const float y = target(rng);
    const auto out = pc::StepCompensator(c, s, y, applied);
    if (out.saturated) continue;
    // S stretches the output by at most 1.7 (its steepest slope).
    DOUBLES_EQUAL(y, pc::PlayForward(c, s, out.drive), 1.7f * Resolution(c, p, 2, 8, y));
    applied = out.drive;
  }
}

TEST(Compensator, MemoryFollowsTheAppliedDriveNotTheCommand) {
  const auto params = PiParams(8, rng);
  const pc::Compensator c =
      pc::MakeCompensator(With(pp::CompensatorKind::kPrandtlIshlinskii, params), 100000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  std::vector<float> z(8);
  for (int i = 0; i < 8; ++i) z[i] = params[2 + i];  // homed: each operator on its upper clamp
  float applied = 0;
  for (int k = 0; k < 3000; ++k) {
    const auto out = pc::StepCompensator(c, s, 400, applied);
    // A lagging chamber: the applied drive trails the command.
    applied += 0.01f * (out.drive - applied);
    for (int i = 0; i < 8; ++i) z[i] = Play(z[i], applied, params[2 + i]);
  }
  pc::StepCompensator(c, s, 400, applied);
  // Equal to the memory's resolution: it holds the applied drive and each state in drive steps.
  for (int i = 0; i < 8; ++i) DOUBLES_EQUAL(z[i], pc::PlayState(c, s, i), c.play.drive_step);
}

TEST(Compensator, HomingPutsEveryOperatorWhereAVentedChamberLeavesIt) {
  const auto params = PiParams(4, rng);
  const pc::Compensator c =
      pc::MakeCompensator(With(pp::CompensatorKind::kPrandtlIshlinskii, params), 100000);
  pc::CompensatorState s;
  pc::StepCompensator(c, s, 300, 80000);
  pc::HomeCompensator(c, s);
  pc::CompensatorState vented;
  pc::HomeCompensator(c, vented);
  for (int k = 0; k < 10; ++k) pc::StepCompensator(c, vented, 300, 0);  // venting changes nothing
  for (int i = 0; i < 4; ++i) {
    DOUBLES_EQUAL(params[2 + i], pc::PlayState(c, s, i), c.play.drive_step / 2);
    DOUBLES_EQUAL(params[2 + i], pc::PlayState(c, vented, i), c.play.drive_step / 2);
  }
}

TEST(Compensator, DrivesBeyondTheLineAreClampedAndSaid) {
  const pc::Compensator c = pc::MakeCompensator(
      With(pp::CompensatorKind::kPrandtlIshlinskii, {0, 0.01f, 0, 0.001f}), 60000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  auto out = pc::StepCompensator(c, s, 5000, 0);  // needs ≈ 455 kPa
  CHECK(out.saturated);
  DOUBLES_EQUAL(60000, out.drive, 0);
  out = pc::StepCompensator(c, s, 100, 0);
  CHECK_FALSE(out.saturated);
  const pc::Compensator offset = pc::MakeCompensator(
      With(pp::CompensatorKind::kPrandtlIshlinskii, {700, 0.01f, 0, 0.001f}), 60000);
  out = pc::StepCompensator(offset, s, 300, 0);  // below what the actuator gives at 0 Pa
  CHECK(out.saturated);
  DOUBLES_EQUAL(0, out.drive, 0);
}

TEST(Compensator, BranchFollowsEachCurveAndBlendsAfterAReversal) {
  // y = 0..1000; rising needs more drive than falling (the falling branch sits higher).
  const auto f = With(pp::CompensatorKind::kBranch,
                      {100, 500, 0, 500, 1000, 0, 50000, 100000, 0, 40000, 100000});
  CHECK(pc::CompensatorParamsError(f) == nullptr);
  const pc::Compensator c = pc::MakeCompensator(f, 100000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  auto out = pc::StepCompensator(c, s, 500, 0);
  DOUBLES_EQUAL(50000, out.drive, 1);
  out = pc::StepCompensator(c, s, 800, 50000);
  DOUBLES_EQUAL(80000, out.drive, 1);
  // Applied reaches 80 kPa, then the target comes down: still on the rising curve until the
  // applied drive has fallen by the dead band.
  out = pc::StepCompensator(c, s, 750, 80000);
  DOUBLES_EQUAL(75000, out.drive, 1);
  out = pc::StepCompensator(c, s, 750, 79000);
  CHECK_FALSE(s.rising);
  DOUBLES_EQUAL(800, s.reversal_output, 1);
  // 50 of the 100-unit band travelled: half way between the branches (75 and 70 kPa).
  DOUBLES_EQUAL(72500, out.drive, 1);
  out = pc::StepCompensator(c, s, 600, 72500);
  DOUBLES_EQUAL(52000, out.drive, 1);  // the falling curve alone
}

TEST(Compensator, ParametersThatCannotBeInvertedAreRefusedWithAReason) {
  using K = pp::CompensatorKind;
  struct Case {
    K kind;
    std::vector<float> params;
  };
  const float nan = std::nanf("");
  const std::vector<Case> bad = {
      {K::kNone, {1}},
      {K::kPrandtlIshlinskii, {0, 0.01f, 0}},                       // odd count
      {K::kPrandtlIshlinskii, {0, 0, 0, 0.01f}},                    // w0 = 0
      {K::kPrandtlIshlinskii, {0, 0.01f, 0, 100, 0.01f, -0.03f}},   // cumulative < 0
      {K::kPrandtlIshlinskii, {0, 0.01f, 100, 100, 0.01f, 0.01f}},  // thresholds repeat
      {K::kPrandtlIshlinskii, {0, 0.01f, -5, 0.01f}},               // negative threshold
      {K::kPrandtlIshlinskii, {nan, 0.01f, 0, 0.01f}},
      {K::kPrandtlIshlinskii, {0, INFINITY, 0, 0.01f}},
      {K::kPrandtlIshlinskii, {0, 1e-30f, 0, 1e30f}},                     // scales overflow float
      {K::kAsymmetricPi, {2.5f, 0, 0.01f, 0, 100, 0.01f, 0.01f, 10, 1}},  // n not an integer
      {K::kAsymmetricPi, {1, 0, 0.01f, 0, 0.01f}},                        // no dead zone
      {K::kAsymmetricPi, {1, 0, 0.01f, 0, 0.01f, 10, -1}},                // slope 0
      {K::kAsymmetricPi, {1, 0, 0.01f, 0, 0.01f, 10, 5, 1, 1}},           // d not increasing
      {K::kBranch, {100, 500, 0, 1000, 0, 100000, 0, 100000, 5}},         // count
      {K::kBranch, {0, 500, 0, 1000, 0, 100000, 0, 100000}},              // band 0
      {K::kBranch, {100, 500, 1000, 0, 0, 100000, 0, 100000}},            // outputs fall
      {K::kBranch, {100, 500, 0, 1000, 100000, 0, 0, 100000}},            // rising not monotone
      {K::kBranch, {100, 500, 0, 1000, 0, 200000, 0, 100000}},            // beyond 100 kPa
  };
  for (const Case& c : bad) {
    const char* why = pc::CompensatorParamsError(With(c.kind, c.params));
    CHECK(why != nullptr);
    CHECK(std::string(why).size() > 10);
  }
  CHECK(pc::CompensatorParamsError(
            With(K::kPrandtlIshlinskii, {0, 0.01f, 0, 100, 0.01f, -0.005f})) == nullptr);
}
