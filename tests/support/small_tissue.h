// A small valid tissue with two depth layers: the reference the hostile-file tests and the fuzzer
// change.
#pragma once

#include "palpa/host/scene_tissue.h"

namespace palpa::testing {

inline host::TissueMap SmallTissue() {
  host::TissueMap m;
  m.name = "small";
  m.unit = "kPa";
  m.pitch_x_mm = 2;
  m.pitch_y_mm = 1;
  m.nx = 3;
  m.ny = 2;
  m.values = {10, 12, 40, 10, 11, 12};
  m.layers = {{2, {1, 1, 3, 1, 1, 1}}, {4, {2, 3, 9, 2, 2, 2}}};
  return m;
}

}  // namespace palpa::testing
