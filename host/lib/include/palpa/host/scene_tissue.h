// A virtual tissue for scenes: a 2-D stiffness map on a regular grid, optionally with force
// against depth at every point (so an input's force can select the depth), sampled by position.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "palpa/host/outcome.h"

namespace palpa::host {

/// At most this many points along either side of a map: a 1 024 × 1 024 grid (tens of MiB as
/// text) is far past any scan (the thesis's force matrices are 159 × 59).
inline constexpr size_t kMaxTissuePoints = 1024;
/// At most this many depth layers per point (the thesis scanned six, 2–7 mm).
inline constexpr size_t kMaxTissueDepths = 32;

/// One depth layer: the force (N) an indenter met at `depth_mm` at every grid point.
struct ForceLayer {
  double depth_mm = 0;
  std::vector<double> force_n;  ///< row-major, as TissueMap::values
};

/// A tissue's stiffness over its surface. Point (i, j) is at x = i·pitch_x_mm, y = j·pitch_y_mm
/// from the map's origin (its corner), so the extent is ((nx−1)·pitch_x, (ny−1)·pitch_y).
struct TissueMap {
  std::string name;
  std::string unit;  ///< of `values`: "kPa" (Young's modulus), "N/mm" (force/depth), "level", ...
  double pitch_x_mm = 1, pitch_y_mm = 1;
  size_t nx = 0, ny = 0;
  std::vector<double> values;  ///< nx·ny, row-major: values[j·nx + i]
  /// Force against depth at every point, depths rising; empty when the map has no depth.
  std::vector<ForceLayer> layers;

  double extent_x_mm() const { return nx > 1 ? static_cast<double>(nx - 1) * pitch_x_mm : 0; }
  double extent_y_mm() const { return ny > 1 ? static_cast<double>(ny - 1) * pitch_y_mm : 0; }
  bool has_depth() const { return !layers.empty(); }
  double At(size_t i, size_t j) const { return values[j * nx + i]; }
  /// The smallest and largest value of the map.
  std::pair<double, double> Range() const;
};

/// Whether a map is whole: sizes within the limits, every value finite, pitches positive, layers
/// of the map's size at rising positive depths. The reason names the first thing wrong.
Outcome CheckTissue(const TissueMap& map);

/// Bilinear interpolation over any row-major grid of the map's shape at (x, y) mm; false outside
/// the map (a point on its edge is inside).
bool InterpolateGrid(const TissueMap& map, const std::vector<double>& grid, double x, double y,
                     double* out);

/// What a contact disc touches: the mean of the map (and of each force layer) over the part of
/// the disc on the map, and how much of the disc that part is.
struct ContactSample {
  double coverage = 0;          ///< 0 (off the tissue) … 1 (wholly on it)
  double value = 0;             ///< mean map value over the covered part
  std::vector<double> force_n;  ///< per layer: mean force over the covered part
};

/// The disc of `diameter_mm` centred at (x, y) sampled on a fixed pattern: rings at most half the
/// finer pitch apart, at least 4 and at most 64 of them, points on each ring about a ring's width
/// apart, each point weighted by the area of the annulus it stands for and interpolated bilinearly;
/// diameter 0 is the single point. Deterministic, and its cost is bounded (about 13 000 points at
/// most).
ContactSample SampleDisc(const TissueMap& map, double x, double y, double diameter_mm);

}  // namespace palpa::host
