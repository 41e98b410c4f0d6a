// A scene drawn as SVG: the tissue's map in colour, the fingers' contact discs about an input
// point, and a path of input positions (palpa scene show, palpa render's record).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "palpa/host/scene_fingers.h"
#include "palpa/host/scene_tissue.h"

namespace palpa::host {

/// The tissue as a colour map from blue (its smallest value) through cyan and yellow to red (its
/// largest), as the thesis drew relative stiffness, y upwards, with a scale bar in the map's unit;
/// each finger's contact disc (numbered from 1, as the command line numbers fingers) with the
/// input at (at_x, at_y); and `path` (input positions, mm) as a line. At most 240 × 240 cells
/// are drawn (a finer map is sampled), so the document stays small.
std::string SceneSvg(const TissueMap& tissue, const FingerLayout& layout, double at_x, double at_y,
                     const std::vector<std::pair<double, double>>& path, const std::string& title);

}  // namespace palpa::host
