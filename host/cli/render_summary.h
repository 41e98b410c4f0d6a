// palpa render's closing summary: what was rendered of the input, and what prediction, a tactile
// array or a pen tablet counted on the way, in words or as JSON.
#pragma once

#include <cstddef>
#include <string>

#include "palpa/host/scene_evdev.h"
#include "palpa/host/scene_predict.h"
#include "palpa/host/scene_tactile.h"

namespace palpa::cli {

struct RenderSummary {
  std::string scene, input, record;
  bool tactile = false;  ///< a tactile array's frames, not a hand's samples
  bool hand = false;     ///< the record has an SVG of the hand's path beside the CSV
  size_t fed = 0;        ///< samples fed to the scene
  size_t total = 0;      ///< samples or frames in the input (live inputs: those fed)
  size_t taken = 0;      ///< tactile: frames rendered
  double horizon_s = 0;  ///< how far ahead prediction rendered (0: not predicting)
  const host::MotionPredictor* predictor = nullptr;
  const host::TactileHold* hold = nullptr;
  const host::TactileUdp* udp = nullptr;
  const host::PenTablet* tablet = nullptr;
};

void PrintRenderSummary(const RenderSummary& s);

}  // namespace palpa::cli
