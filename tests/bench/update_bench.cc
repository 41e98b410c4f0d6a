// Firmware update under power cuts: a thousand cuts at random flash bytes of a whole update
// (erase, write, activate, trial boot, confirm), each followed by a boot; the tally of what
// booted, by where the cut fell. A board that boots nothing valid is a failure of the design.
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "update_scenario.h"

namespace pt = palpa::testing;

int main(int argc, char** argv) {
  const int cuts = argc > 1 ? std::atoi(argv[1]) : 1000;
  const uint64_t total = pt::UpdateFlashBytes(1);
  std::mt19937 rng(2026);
  struct Tally {
    int old_image = 0, new_image = 0, none = 0;
  };
  std::map<std::string, Tally> by_phase;
  Tally all;
  for (int k = 0; k < cuts; ++k) {
    // As in the tests: most cuts anywhere, a share among the small record writes at the end.
    const uint64_t cut = k % 10 < 7 ? rng() % (total + 200) : total - 150 + rng() % 300;
    const pt::CutOutcome o = pt::CutPowerDuringUpdate(cut, static_cast<uint32_t>(k + 1));
    Tally& t = by_phase[o.phase];
    if (!o.valid) {
      ++t.none;
      ++all.none;
    } else if (o.is_new) {
      ++t.new_image;
      ++all.new_image;
    } else {
      ++t.old_image;
      ++all.old_image;
    }
  }
  std::printf("== firmware update: %d power cuts over %llu flash bytes of one update ==\n", cuts,
              static_cast<unsigned long long>(total));
  for (const auto& [phase, t] : by_phase) {
    std::printf("  cut during %-14s boots old %4d  new %4d  nothing valid %d\n", phase.c_str(),
                t.old_image, t.new_image, t.none);
  }
  std::printf("  total: old %d, new %d, nothing valid %d\n", all.old_image, all.new_image,
              all.none);
  return all.none == 0 ? 0 : 1;
}
