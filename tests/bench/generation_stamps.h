// palpa-sim's --stamp file read back: when each generation of a stream was applied and when it
// first reached the DAC, on CLOCK_MONOTONIC, the clock the host's own stamps are taken on.
#pragma once

#include <time.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace palpa::bench {

inline int64_t MonotonicNs() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<int64_t>(t.tv_sec) * 1000000000LL + t.tv_nsec;
}

struct GenerationStamps {
  std::map<uint32_t, int64_t> applied, dac;  ///< generation → CLOCK_MONOTONIC ns
};

/// The stamps of one stream ("setpoints" or "targets") from palpa-sim's file (complete once it
/// stopped).
inline GenerationStamps ReadGenerationStamps(const std::string& path, const std::string& stream) {
  GenerationStamps s;
  std::ifstream in(path);
  std::string name, kind;
  uint32_t generation;
  long long ns;
  while (in >> name >> generation >> kind >> ns) {
    if (name == stream) (kind == "dac" ? s.dac : s.applied)[generation] = ns;
  }
  return s;
}

/// The host's stamps (generation → when it was asked for) against the board's: the whole way to
/// the DAC, the link up to the dispatch, and the wait for the next tick, in ms.
struct LatencySplit {
  std::vector<double> total, link, tick;
};
inline LatencySplit Match(const std::map<uint32_t, int64_t>& called, const GenerationStamps& s) {
  LatencySplit out;
  for (const auto& [g, t] : called) {
    const auto applied = s.applied.find(g), dac = s.dac.find(g);
    if (applied == s.applied.end() || dac == s.dac.end()) continue;
    out.total.push_back(static_cast<double>(dac->second - t) / 1e6);
    out.link.push_back(static_cast<double>(applied->second - t) / 1e6);
    out.tick.push_back(static_cast<double>(dac->second - applied->second) / 1e6);
  }
  return out;
}

inline void PrintLatency(const char* what, std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const auto at = [&](double p) {
    return v[static_cast<size_t>(p * static_cast<double>(v.size() - 1))];
  };
  std::printf("  %-34s p50 %6.3f ms  p99 %6.3f ms  max %6.3f ms\n", what, at(0.5), at(0.99),
              v.back());
}

}  // namespace palpa::bench
