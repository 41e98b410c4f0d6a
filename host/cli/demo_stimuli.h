// The thesis's discrimination stimuli: a "tumour" is one finger, or two adjacent fingers, stiffer
// than the rest; none when all are equal.
#pragma once

#include <cstddef>
#include <vector>

namespace palpa::cli {

/// Every level combination of `fingers` fingers over levels 0..levels-1 that the rule allows:
/// all equal; one finger higher than the others (which are equal); two adjacent fingers equal and
/// higher than the others (which are equal, and exist).
std::vector<std::vector<int>> TumourCombinations(size_t fingers, int levels);

}  // namespace palpa::cli
