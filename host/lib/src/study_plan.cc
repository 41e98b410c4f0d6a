// The trial list: seeded shuffles per block (a Fisher–Yates of our own over mt19937_64, whose
// output the standard fixes, so every platform draws the same order), practice first, breaks.
#include "palpa/host/study_plan.h"

#include <random>

namespace palpa::host {
namespace {

/// A uniform index below n from the engine's raw outputs (std::uniform_int_distribution is
/// not the same on every standard library).
size_t Below(std::mt19937_64& rng, size_t n) {
  const uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  uint64_t x;
  do x = rng();
  while (x >= limit);
  return static_cast<size_t>(x % n);
}

void Shuffle(std::vector<int>& v, std::mt19937_64& rng) {
  for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[Below(rng, i)]);
}

}  // namespace

uint64_t StudySeed(const Study& study, const std::string& participant) {
  uint64_t h = 14695981039346656037ull;  // FNV-1a
  for (const char c : StudyToJson(study).dump() + '\n' + participant) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h >> 11;
}

StudyPlan PlanStudy(const Study& study, uint64_t seed) {
  StudyPlan plan;
  plan.seed = seed;
  std::mt19937_64 rng(seed);
  for (size_t b = 0; b < study.blocks.size(); ++b) {
    const StudyBlock& block = study.blocks[b];
    std::vector<ScheduledTrial> trials;
    auto add = [&](int condition, bool practice) {
      ScheduledTrial t;
      t.block = static_cast<int>(b);
      t.condition = condition;
      t.practice = practice;
      trials.push_back(t);
    };
    const int n = static_cast<int>(study.conditions.size());
    if (block.kind == BlockKind::kStaircase) {
      for (int i = 0; i < block.practice + block.staircase.max_trials; ++i) {
        add(-1, i < block.practice);
        trials.back().comparison_second = Below(rng, 2) == 1;
      }
    } else {
      std::vector<int> practice;
      for (int i = 0; i < block.practice; ++i) practice.push_back(static_cast<int>(Below(rng, n)));
      for (int c : practice) add(c, true);
      std::vector<int> order;
      for (int r = 0; r < block.repetitions; ++r)
        for (int c = 0; c < n; ++c) order.push_back(c);
      if (block.randomise) Shuffle(order, rng);
      for (int c : order) add(c, false);
    }
    int scored = 0;
    for (size_t i = 0; i < trials.size(); ++i) {
      ScheduledTrial& t = trials[i];
      t.break_before = (i == 0 && b > 0) || (!t.practice && block.break_every > 0 && scored > 0 &&
                                             scored % block.break_every == 0);
      if (!t.practice) ++scored;
      t.index = static_cast<int>(plan.trials.size());
      plan.trials.push_back(t);
    }
  }
  return plan;
}

nlohmann::ordered_json PlanToJson(const Study& study, const StudyPlan& plan) {
  nlohmann::ordered_json order = nlohmann::ordered_json::array();
  for (const ScheduledTrial& t : plan.trials) {
    order.push_back(
        {{"index", t.index},
         {"block", study.blocks[t.block].name},
         {"condition", t.condition < 0 ? "staircase" : study.conditions[t.condition].name},
         {"practice", t.practice},
         {"break_before", t.break_before}});
  }
  return order;
}

}  // namespace palpa::host
