// Tissues from greyscale images: a PGM file (P2 or P5, what image tools export) with a stated
// scale — millimetres per pixel and the stiffness at black and at white.
#pragma once

#include <string>

#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"
#include "palpa/host/scene_tissue.h"

namespace palpa::host {

/// 1 024 × 1 024 pixels as ASCII (P2) is at most about 6 MiB.
inline constexpr FileLimits kTissueImageLimits{"tissue image", 8 * 1024 * 1024};

/// How an image becomes a map: each pixel a grid point `mm_per_pixel` apart, grey g of maxval M
/// the value value_at_black + (g / M) · (value_at_white − value_at_black) in `unit`.
struct ImageScale {
  std::string name, unit;
  double mm_per_pixel = 0;
  double value_at_black = 0, value_at_white = 0;
};

/// A PGM image's bytes as a map. The image's top row is the map's largest y, so the map drawn
/// with y upwards looks as the image does. 2 … 1 024 pixels a side, maxval 1 … 65 535 (two bytes
/// a pixel, big-endian, above 255 in P5). `source` names it in errors ("PATH: pixel (3, 7): 300
/// is above the maxval 255").
Result<TissueMap> ParseTissueImage(const std::string& bytes, const ImageScale& scale,
                                   const std::string& source);
/// ParseTissueImage of a file read within kTissueImageLimits.
Result<TissueMap> LoadTissueImage(const std::string& path, const ImageScale& scale);

}  // namespace palpa::host
