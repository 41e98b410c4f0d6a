// Edge lag at every cube face a finger crosses on a pass, either way: where the rule's target for
// the finger crosses half of the face's change, against where the finger's true output crosses
// the same level the same way — along the finger's path, positive behind, negative ahead. Faces
// whose change is under a third of the scene's target range are not timed: the held-out unit's
// static error is of that size, so crossing half of such a change measures the curve, not lag.
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include "palpa/host/scene_phantom.h"

namespace palpa::bench {

struct EdgeCrossing {
  size_t finger = 0;
  double face_mm = 0;
  int direction = 0;    ///< +1: the finger moving to larger x
  double lag_mm = NAN;  ///< NAN: the output did not cross within kEdgeSearchMm of the path
};

/// How far along the path a true crossing is looked for, either side of the rule's.
constexpr double kEdgeSearchMm = 8;

/// `place` and `output`: the finger's x and true output every tick of the pass; `target(x)`:
/// the rule's target for the finger at x; `range`: the scene's target range.
inline std::vector<EdgeCrossing> EdgeCrossings(size_t finger, const std::vector<double>& place,
                                               const std::vector<double>& output,
                                               const std::function<double(double)>& target,
                                               double range) {
  std::vector<EdgeCrossing> edges;
  std::vector<double> s(place.size(), 0);  // distance the finger travelled
  for (size_t k = 1; k < place.size(); ++k) s[k] = s[k - 1] + std::fabs(place[k] - place[k - 1]);
  for (const host::Inclusion& c : host::ThreeCubePhantom().inclusions) {
    for (const double face : {c.x_mm - c.size_x_mm / 2, c.x_mm + c.size_x_mm / 2}) {
      const double outside = target(face - 3), inside = target(face + 3);
      if (std::fabs(inside - outside) < range / 3) continue;  // a change within static error
      const double level = (outside + inside) / 2;
      double at = face;  // where the rule's target crosses the level near the face
      for (double x = face - 3; x <= face + 3; x += 0.01) {
        if ((target(x) - level) * (inside - level) >= 0) {
          at = x;
          break;
        }
      }
      for (size_t k = 1; k < place.size(); ++k) {
        if (!((place[k - 1] - at) * (place[k] - at) < 0)) continue;
        const int direction = place[k] > place[k - 1] ? 1 : -1;
        // Moving to larger x the target goes from outside to inside; back, the reverse.
        const double sense = direction * (inside - outside) > 0 ? 1 : -1;
        EdgeCrossing e{finger, face, direction, NAN};
        for (size_t j = 1; j < place.size(); ++j) {
          if (std::fabs(s[j] - s[k]) > kEdgeSearchMm) continue;
          if (sense * (output[j - 1] - level) < 0 && sense * (output[j] - level) >= 0) {
            const double lag = s[j] - s[k];
            if (std::isnan(e.lag_mm) || std::fabs(lag) < std::fabs(e.lag_mm)) e.lag_mm = lag;
          }
        }
        edges.push_back(e);
      }
    }
  }
  return edges;
}

}  // namespace palpa::bench
