// Generation of the discrimination stimuli (18 for three fingers at three levels, 9 for two).
#include "demo_stimuli.h"

namespace palpa::cli {

std::vector<std::vector<int>> TumourCombinations(size_t fingers, int levels) {
  std::vector<std::vector<int>> out;
  for (int level = 0; level < levels; ++level)
    out.push_back(std::vector<int>(fingers, level));  // no tumour
  for (int low = 0; low < levels; ++low) {
    for (int high = low + 1; high < levels; ++high) {
      for (size_t at = 0; at < fingers; ++at) {  // one finger stiffer
        std::vector<int> c(fingers, low);
        c[at] = high;
        out.push_back(c);
      }
      for (size_t at = 0; at + 1 < fingers && fingers > 2; ++at) {  // two adjacent, with a rest
        std::vector<int> c(fingers, low);
        c[at] = c[at + 1] = high;
        out.push_back(c);
      }
    }
  }
  return out;
}

}  // namespace palpa::cli
