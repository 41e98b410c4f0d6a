// The correction's bucket lookup against the search it replaced: the same command, to the bit,
// for every input (points, both sides of them, the buckets' edges, the ends and beyond), on
// corrections of every length, rising and falling, spaced evenly and bunched.
#include "palpa/core/correction_lookup.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "palpa/core/curve.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

namespace {

/// The search the tick made before: the nearest end's offset beyond the points, else a bisection
/// through them (Interpolate).
float Searched(const std::vector<float>& command, const std::vector<float>& produced, float at) {
  const uint8_t count = static_cast<uint8_t>(produced.size());
  const uint8_t last = static_cast<uint8_t>(count - 1);
  const bool up = produced[last] > produced[0];
  const float low = up ? produced[0] : produced[last], high = up ? produced[last] : produced[0];
  if (at < low || at > high) {
    const uint8_t end = (at < low) == up ? 0 : last;
    return at + (command[end] - produced[end]);
  }
  return pc::Interpolate(produced.data(), command.data(), count, at);
}

uint32_t Bits(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

/// Every input worth asking about: the points and their neighbouring floats, the middles, each
/// bucket's edge and its neighbours, the ends and beyond them, and random ones across the range.
std::vector<float> Probes(float sign, const pc::CorrectionBranch& b,
                          const std::vector<float>& produced, std::mt19937& rng) {
  std::vector<float> probes;
  auto around = [&probes](float v) {
    probes.push_back(v);
    probes.push_back(std::nextafter(v, -INFINITY));
    probes.push_back(std::nextafter(v, INFINITY));
  };
  for (size_t i = 0; i < produced.size(); ++i) {
    around(produced[i]);
    if (i > 0) around(0.5f * (produced[i - 1] + produced[i]));
  }
  for (int k = 0; k <= pc::kCorrectionBuckets; ++k)
    around(sign * (b.point[0] + static_cast<float>(k) / b.per_bucket));
  const float low = std::min(produced.front(), produced.back());
  const float high = std::max(produced.front(), produced.back());
  const float span = high - low;
  around(low - 0.25f * span);
  around(high + 0.25f * span);
  std::uniform_real_distribution<float> across(low - 0.1f * span, high + 0.1f * span);
  for (int i = 0; i < 400; ++i) probes.push_back(across(rng));
  return probes;
}

}  // namespace

TEST_GROUP(CorrectionLookup){};

TEST(CorrectionLookup, GivesTheSearchsCommandToTheBitForEveryInput) {
  std::mt19937 rng(33);
  std::uniform_real_distribution<float> unit(0, 1);
  int probed = 0;
  for (int count = 2; count <= pp::kMaxCorrectionPoints; ++count) {
    for (const float sign : {1.0f, -1.0f}) {  // a pressure line's and a vacuum line's
      for (const bool bunched : {false, true}) {
        for (int trial = 0; trial < 8; ++trial) {
          // Commands 10-90 % of 100 kPa as calibration takes them; produced a little short of
          // them, unevenly, or (bunched) with most points crowded into a few kPa.
          std::vector<pp::CorrectionPoint> points;
          float at = 10000 + 2000 * unit(rng);
          const float hysteresis = 300 + 700 * unit(rng);  // falling above rising
          for (int i = 0; i < count; ++i) {
            const float command =
                10000 + 80000.0f * static_cast<float>(i) / static_cast<float>(count - 1);
            const float falling = at + hysteresis;
            points.push_back({static_cast<int32_t>(sign * std::round(command)),
                              static_cast<int32_t>(sign * std::round(at)),
                              static_cast<int32_t>(sign * std::round(falling))});
            at += bunched && i % 5 != 4 ? 1 + 300 * unit(rng) : 2000 + 12000 * unit(rng);
          }
          pc::Correction c;
          pc::MakeCorrection(points.data(), static_cast<uint8_t>(count), c);
          std::vector<float> command, rising, falling;
          for (const pp::CorrectionPoint& p : points) {
            command.push_back(static_cast<float>(p.command_pa));
            rising.push_back(static_cast<float>(p.rising_pa));
            falling.push_back(static_cast<float>(p.falling_pa));
          }
          for (const bool on_rising : {true, false}) {
            const std::vector<float>& produced = on_rising ? rising : falling;
            const pc::CorrectionBranch& b = on_rising ? c.rising : c.falling;
            for (float probe : Probes(c.sign, b, produced, rng)) {
              const float expected = Searched(command, produced, probe);
              const float got = pc::CorrectionCommand(c, b, probe);
              if (Bits(expected) != Bits(got)) {
                std::string where;
                for (const pp::CorrectionPoint& p : points)
                  where += " {" + std::to_string(p.command_pa) + ", " +
                           std::to_string(p.rising_pa) + ", " + std::to_string(p.falling_pa) + "}";
                FAIL(("points" + where + (on_rising ? ", rising" : ", falling") + ", input " +
                      std::to_string(probe) + ": searched " + std::to_string(expected) +
                      ", looked up " + std::to_string(got))
                         .c_str());
              }
              ++probed;
            }
          }
        }
      }
    }
  }
  CHECK(probed > 100000);
}

TEST(CorrectionLookup, EvenlySpacedPointsLieOneToABucketAtMost) {
  // Calibration's points (commands evenly over 10-90 %, the regulator's output 4 % short at the
  // bottom, 7 % at the top): a lookup steps past one point at most.
  for (int count = 2; count <= pp::kMaxCorrectionPoints; ++count) {
    std::vector<pp::CorrectionPoint> points;
    for (int i = 0; i < count; ++i) {
      const float u = static_cast<float>(i) / static_cast<float>(count - 1);
      const float command = 10000 + 80000 * u;
      const auto produced = static_cast<int32_t>(command * (0.96f - 0.03f * u));
      points.push_back({static_cast<int32_t>(command), produced, produced + 500});
    }
    pc::Correction c;
    pc::MakeCorrection(points.data(), static_cast<uint8_t>(count), c);
    const pc::CorrectionBranch& b = c.rising;
    LONGS_EQUAL(1, b.first[0]);
    for (int k = 1; k < pc::kCorrectionBuckets; ++k) CHECK(b.first[k] - b.first[k - 1] <= 1);
    LONGS_EQUAL(count - 1, b.first[pc::kCorrectionBuckets - 1]);
  }
}
