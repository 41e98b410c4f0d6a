// What several scene tests start from: the documented three-cube scene and its phantom's map.
#pragma once

#include "palpa/host/scene_phantom.h"

#include "CppUTest/TestHarness.h"

namespace palpa::testing {

inline constexpr char kThreeCubeScene[] = PALPA_DOCS_DIR "/examples/scene_three_cube.json";

/// The three-cube phantom's tissue map (the phantom must generate).
inline host::TissueMap ThreeCubeMap() {
  const auto m = host::GeneratePhantom(host::ThreeCubePhantom());
  CHECK_TEXT(m.ok(), m.message.c_str());
  return m.value;
}

}  // namespace palpa::testing
