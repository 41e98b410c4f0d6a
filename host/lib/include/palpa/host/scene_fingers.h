// Finger layouts for scenes: where each finger sits relative to the input point, and the contact
// disc over which it feels the tissue; the thesis's right triangle, a row of N, a jamming pair.
#pragma once

#include <string>
#include <vector>

#include "palpa/host/outcome.h"
#include "palpa/host/scene_tissue.h"

namespace palpa::host {

/// A finger's place relative to the input point, in the tissue's x and y (mm).
struct FingerPlace {
  double dx_mm = 0, dy_mm = 0;
};

struct FingerLayout {
  std::string name;
  std::vector<FingerPlace> fingers;
  /// Every finger feels the mean over a disc this wide (0: the single point under it).
  double contact_diameter_mm = 0;
};

/// At most as many fingers as a board drives.
inline constexpr size_t kMaxLayoutFingers = 8;

/// 1 … kMaxLayoutFingers fingers at finite offsets within 500 mm of the input, a contact disc of
/// 0 … 100 mm; the reason names the field ("fingers[2].dx_mm: ...").
Outcome CheckLayout(const FingerLayout& layout);

/// The thesis's three fingers (§5.3.4.2): a right-angled triangle whose right-angle vertex
/// (finger 0) follows the input, finger 1 `spacing_mm` along +x, finger 2 `spacing_mm` along +y.
FingerLayout RightTriangleLayout(double spacing_mm, double contact_diameter_mm);
/// `count` fingers `spacing_mm` apart along x, centred on the input, finger 0 at the smallest x.
FingerLayout RowLayout(size_t count, double spacing_mm, double contact_diameter_mm);
/// The two fingers of the jamming system (§5.4): a row of two.
FingerLayout JammingPairLayout(double spacing_mm, double contact_diameter_mm);
/// The layout turned by `degrees` counter-clockwise about the input point (a hand at an angle).
FingerLayout Rotated(FingerLayout layout, double degrees);

/// What each finger touches with the input at (x, y), in the layout's order.
std::vector<ContactSample> SampleFingers(const TissueMap& map, const FingerLayout& layout,
                                         double x_mm, double y_mm);

}  // namespace palpa::host
